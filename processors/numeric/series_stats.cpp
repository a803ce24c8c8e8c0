#include "processors/numeric/series_stats.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "processors/numeric/line_fit.hpp"

namespace gyrocal::numeric {

namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
}

MeanStats DescribeSeries(const std::vector<double>& x, int batches) {
    MeanStats s;
    s.n = static_cast<int>(x.size());
    if (s.n == 0) {
        s.mean = s.std = s.sem = kNaN;
        return s;
    }
    double sum = 0;
    for (double v : x) sum += v;
    s.mean = sum / s.n;
    double ss = 0;
    for (double v : x) ss += (v - s.mean) * (v - s.mean);
    s.std = s.n > 1 ? std::sqrt(ss / (s.n - 1)) : 0.0;

    const int b = std::min(batches, s.n / 2);
    if (b < 4) {
        s.sem = s.n > 1 ? s.std / std::sqrt(static_cast<double>(s.n)) : kNaN;
        return s;
    }
    // Equal-count batches; the remainder (< b samples) is spread over the first batches.
    std::vector<double> bm(b), bt(b);
    const int base = s.n / b, extra = s.n % b;
    int at = 0;
    for (int k = 0; k < b; ++k) {
        const int len = base + (k < extra ? 1 : 0);
        double acc = 0;
        for (int i = 0; i < len; ++i) acc += x[at + i];
        bm[k] = acc / len;
        bt[k] = at + 0.5 * (len - 1);  // centre of the batch, in sample index
        at += len;
    }
    const LineFit line = FitLine(bt, bm);
    s.sem = line.resid_std / std::sqrt(static_cast<double>(b));
    s.batches = b;
    return s;
}

NoiseLevel PooledNoiseLevel(const std::vector<std::vector<double>>& series) {
    NoiseLevel out;
    std::vector<std::vector<double>> resid;
    size_t max_n = 0;
    double ss = 0;
    for (const std::vector<double>& x : series) {
        if (x.size() < 4) continue;
        double mean = 0;
        for (double v : x) mean += v;
        mean /= static_cast<double>(x.size());
        std::vector<double> r(x.size());
        for (size_t i = 0; i < x.size(); ++i) {
            r[i] = x[i] - mean;
            ss += r[i] * r[i];
        }
        out.n += static_cast<int>(x.size());
        max_n = std::max(max_n, x.size());
        resid.push_back(std::move(r));
    }
    if (resid.empty()) {
        out.var = kNaN;
        return out;
    }
    // Autocovariance at lag k, pooled (each series contributes its own pairs).
    auto gamma = [&](size_t k) {
        double acc = 0;
        int pairs = 0;
        for (const auto& r : resid) {
            for (size_t i = 0; i + k < r.size(); ++i) acc += r[i] * r[i + k];
            pairs += r.size() > k ? static_cast<int>(r.size() - k) : 0;
        }
        return pairs > 0 ? acc / pairs : 0.0;
    };
    const double g0 = gamma(0);
    if (!(g0 > 0)) {
        out.var = 0;
        return out;
    }
    // Geyer's initial monotone sequence: Gamma_m = gamma(2m) + gamma(2m+1) is positive and
    // decreasing for a reversible process; sum while positive, each capped by the previous one
    // (which keeps estimation noise at large lags out), lags up to a quarter of the longest series.
    double sum_pairs = 0, prev_pair = std::numeric_limits<double>::infinity();
    for (size_t m = 0; 2 * m + 1 < max_n / 4 + 2; ++m) {
        const double pair = std::min(prev_pair, gamma(2 * m) + gamma(2 * m + 1));
        if (pair <= 0) break;
        sum_pairs += pair;
        prev_pair = pair;
    }
    double tau = std::max(1.0, (2 * sum_pairs - g0) / g0);
    // Removing each series' mean takes out about tau samples' worth of variance from it, from
    // the variance and from every autocovariance alike (E[gamma_k] ~ gamma_k - var*tau/n), so
    // the sums above run low by O(tau/n). First-order correction: divide the variance by
    // sum(n_i - tau) instead of sum(n_i), and add the lost tau/n share back to tau.
    const double k = static_cast<double>(resid.size());
    const double n = static_cast<double>(out.n);
    const double dof = std::max(1.0, n - k * tau);
    out.var = ss / dof;
    tau = tau / std::max(0.5, 1.0 - k * tau / n);
    out.tau_int = tau;
    return out;
}

}  // namespace gyrocal::numeric
