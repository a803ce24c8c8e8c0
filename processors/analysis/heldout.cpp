#include "processors/analysis/heldout.hpp"

#include <algorithm>
#include <cmath>
#include <map>

#include "processors/model/inputs.hpp"
#include "processors/numeric/least_squares.hpp"

namespace gyrocal::analysis::detail {

using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::VectorXd;

Split MakeSplit(const std::vector<Bin>& bins, const AnalysisOptions& o) {
    Split s;
    if (bins.empty()) return s;
    const int every = std::max(2, static_cast<int>(std::lround(1.0 / o.holdout_fraction)));
    const double t_first = bins.front().start_utime * 1e-6;
    auto block_of = [&](double t_s) {
        return static_cast<long>(std::floor((t_s - t_first) / o.holdout_block_s));
    };
    auto held_block = [&](long b) { return b % every == 1; };
    std::map<long, int> blocks;
    for (size_t i = 0; i < bins.size(); ++i) {
        const Bin& b = bins[i];
        const double start_s = b.start_utime * 1e-6, end_s = b.end_utime * 1e-6;
        const long k = block_of(start_s);
        if (held_block(k) && block_of(end_s - 1e-6) == k) {
            s.held.push_back(static_cast<Index>(i));
            s.held_block.push_back(
                blocks.emplace(k, static_cast<int>(blocks.size())).first->second);
            continue;
        }
        // Training bins keep cv_guard_s away from every held-out block.
        const bool near = held_block(block_of(start_s - o.cv_guard_s)) ||
                          held_block(block_of(end_s + o.cv_guard_s)) || held_block(k);
        if (!near) s.train.push_back(static_cast<Index>(i));
    }
    s.n_blocks = static_cast<int>(blocks.size());
    return s;
}

model::Model FitModel(const std::vector<std::string>& terms, double t0, const BinnedRun& binned,
                      const std::vector<Index>& rows, const LsFit& f) {
    model::Model m;
    m.quantity = model::kOffsetQuantity;
    m.term_names = terms;
    // Nuisance columns (candidates.hpp) follow the terms' in the fit: not part of the model.
    const auto p = static_cast<Index>(terms.size());
    m.coeffs = f.coeffs.head(p);
    m.covariance = f.covariance.topLeftCorner(p, p);
    m.t0_c = t0;
    m.temp_min_c = INFINITY;
    m.temp_max_c = -INFINITY;
    for (Index i : rows) {
        m.temp_min_c = std::min(m.temp_min_c, binned.bins()[static_cast<size_t>(i)].temp_c);
        m.temp_max_c = std::max(m.temp_max_c, binned.bins()[static_cast<size_t>(i)].temp_c);
    }
    m.residual_rms = std::sqrt(f.rss / static_cast<double>(rows.size()));
    m.n_points = static_cast<int32_t>(rows.size());
    m.method = "analysis";
    return m;
}

VectorXd Residuals(const BinnedRun& binned, const model::Model& offset,
                   const std::vector<Index>& rows) {
    const VectorXd v = binned.Values(offset);
    VectorXd r(static_cast<Index>(rows.size()));
    for (size_t k = 0; k < rows.size(); ++k)
        r[static_cast<Index>(k)] = binned.bins()[static_cast<size_t>(rows[k])].gyro_v - v[rows[k]];
    return r;
}

namespace {
// Sensitivity at each bin (at rest), NaN where it cannot be evaluated.
VectorXd SensitivityAt(const BinnedRun& binned, const model::Model& sens,
                       const std::vector<Index>& rows) {
    const VectorXd all = binned.Values(sens);
    return all(rows);
}
}  // namespace

double MeanInverseSensitivity(const BinnedRun& binned, const model::Model& sens,
                              const std::vector<Index>& rows) {
    const VectorXd s = SensitivityAt(binned, sens, rows);
    if (s.size() == 0 || !s.allFinite() || (s.array() == 0.0).any()) return kNan;
    return s.cwiseAbs().cwiseInverse().mean();
}

ErrorFigures ErrorsOn(const BinnedRun& binned, const VectorXd& r, const std::vector<Index>& rows,
                      const std::vector<int>& block, const std::optional<model::Model>& sens) {
    ErrorFigures e;
    if (r.size() == 0 || !r.allFinite()) return e;
    e.offset_rms_v = std::sqrt(r.squaredNorm() / static_cast<double>(r.size()));
    if (!sens) return e;
    const VectorXd s = SensitivityAt(binned, *sens, rows);
    if (!s.allFinite() || (s.array() == 0.0).any()) return e;
    const VectorXd rate = r.cwiseQuotient(s);
    e.rate_rms_dps = std::sqrt(rate.squaredNorm() / static_cast<double>(rate.size()));
    std::map<int, std::pair<double, double>> angle;  // block -> (deg, s)
    const double period_s = SamplePeriodS(binned.run());
    for (size_t k = 0; k < rows.size(); ++k) {
        const double d = binned.bins()[static_cast<size_t>(rows[k])].n * period_s;
        angle[block[k]].first += rate[static_cast<Index>(k)] * d;
        angle[block[k]].second += d;
    }
    double ss = 0.0;
    for (const auto& [b, a] : angle) ss += std::pow(a.first / a.second * 3600.0, 2);
    e.drift_dph = std::sqrt(ss / static_cast<double>(angle.size()));
    return e;
}

namespace {

// The long-run sum of the score terms u (Bartlett weights up to hac_lag, products only within a
// block), never below the white sum u'u: never more certain than white residuals would make it.
double BlockHacSum(const VectorXd& u, const std::vector<int>& block, int hac_lag) {
    const Index n = u.size();
    double s = u.squaredNorm();
    for (int l = 1; l <= hac_lag; ++l) {
        const double w = 1.0 - l / (hac_lag + 1.0);
        for (Index i = l; i < n; ++i)
            if (block[static_cast<size_t>(i)] == block[static_cast<size_t>(i - l)])
                s += 2.0 * w * u[i] * u[i - l];
    }
    return std::max(s, u.squaredNorm());
}

}  // namespace

Gain HeldOutGain(const VectorXd& before, const VectorXd& after, const std::vector<int>& block,
                 int hac_lag) {
    Gain g;
    const Index n = before.size();
    if (n < 2 || !before.allFinite() || !after.allFinite()) return g;
    g.mean_v2 = (before.cwiseAbs2() - after.cwiseAbs2()).mean();
    // delta = what the added terms predict on the held-out bins; regress the declared model's
    // held-out residual on it. Under "the terms are noise" the slope is 0; a real effect gives ~1.
    const VectorXd delta = before - after;
    const double sdd = delta.squaredNorm();
    if (!(sdd > 0.0)) return g;
    g.slope = delta.dot(before) / sdd;
    const VectorXd u = delta.cwiseProduct(before - g.slope * delta);  // score terms
    const double var = BlockHacSum(u, block, hac_lag) / (sdd * sdd);
    g.z = g.slope / std::sqrt(var);
    return g;
}

double LossDifferenceZ(const VectorXd& a, const VectorXd& b, const std::vector<int>& block,
                       int hac_lag) {
    const Index n = a.size();
    if (n < 2 || b.size() != n || !a.allFinite() || !b.allFinite()) return kNan;
    const VectorXd d = a.cwiseAbs2() - b.cwiseAbs2();
    const double mean = d.mean();
    const VectorXd u = d.array() - mean;
    const double var = BlockHacSum(u, block, hac_lag) / (static_cast<double>(n) * n);
    return var > 0.0 ? mean / std::sqrt(var) : kNan;
}

double MeanLeverage(const MatrixXd& x_train, const MatrixXd& x_held) {
    return numeric::MeanLeverage(x_train, x_held);
}

void ExpectedAfter(const LsFit& fit, const MatrixXd& x_held, double inv_sens, SensorResult* r) {
    const Index n = x_held.rows(), p = fit.coeffs.size();
    const Index n_train = fit.residuals.size();
    if (n == 0 || n_train <= p) return;
    // Mean prediction variance x' C x over the held-out bins: how far the coefficients fitted on
    // the training bins may put the model off on them, by their own (robust) covariance.
    const double pred_var = (x_held * fit.covariance).cwiseProduct(x_held).rowwise().sum().mean();
    const double resid_var = numeric::ResidualVariance(fit.rss, n_train, p);
    if (!(pred_var >= 0.0) || !std::isfinite(resid_var)) return;
    r->prediction_rms_v = std::sqrt(pred_var);
    r->expected_after_offset_rms_v = std::sqrt(resid_var + pred_var);
    r->expected_after_rate_rms_dps = r->expected_after_offset_rms_v * inv_sens;
    r->prediction_rms_dps = r->prediction_rms_v * inv_sens;
}

}  // namespace gyrocal::analysis::detail
