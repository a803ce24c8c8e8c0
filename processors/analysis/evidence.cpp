#include "processors/analysis/evidence.hpp"

#include <algorithm>
#include <cmath>
#include <random>
#include <string>

#include "lcmtypes/text/number.hpp"
#include "processors/analysis/null.hpp"
#include "processors/numeric/least_squares.hpp"

namespace gyrocal::analysis::detail {

using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::VectorXd;

Surrogates MakeSurrogates(const BinnedRun& binned, const VectorXd& residual_all,
                          const AnalysisOptions& o) {
    Surrogates s;
    if (residual_all.size() != static_cast<Index>(binned.size()) || binned.size() < 8) return s;
    s.floor_v = NoiseFloor(binned.bins(), residual_all).offset_rms_v;
    s.model = MeasureNoise(binned.bins(), residual_all, binned.bin_s(), s.floor_v);
    const SurrogateNoise draw(s.model, binned.bins(), binned.bin_s());
    std::mt19937_64 rng(o.surrogate_seed);
    for (int k = 0; k < o.surrogates; ++k) s.noise.push_back(draw.Draw(rng));
    return s;
}

namespace {

std::vector<WindowSpec> Windows(const BinnedRun& b) {
    std::vector<WindowSpec> out;
    const std::vector<Bin>& bins = b.bins();
    const double t_first = bins.front().mid_utime * 1e-6;
    for (double len : {600.0, 1200.0, 2400.0}) {
        std::vector<WindowSpec> tiles;
        for (size_t i = 0; i < bins.size(); ++i) {
            const auto k = static_cast<size_t>((bins[i].mid_utime * 1e-6 - t_first) / len);
            while (tiles.size() <= k)
                tiles.push_back({text::Sig(tiles.size() * len, 4) + "-" +
                                     text::Sig((tiles.size() + 1) * len, 4) + " s from the start",
                                 {},
                                 len});
            tiles[k].rows.push_back(static_cast<Index>(i));
        }
        for (WindowSpec& w : tiles)
            if (w.rows.size() >= 3) out.push_back(std::move(w));
    }
    double lo = INFINITY, hi = -INFINITY;
    for (const Bin& x : bins) lo = std::min(lo, x.temp_c), hi = std::max(hi, x.temp_c);
    const int bands = 8;
    if (!(hi > lo)) return out;
    std::vector<WindowSpec> temp(bands);
    for (int k = 0; k < bands; ++k)
        temp[static_cast<size_t>(k)].where = text::Sig(lo + k * (hi - lo) / bands, 3) + ".." +
                                             text::Sig(lo + (k + 1) * (hi - lo) / bands, 3) +
                                             " degC";
    for (size_t i = 0; i < bins.size(); ++i) {
        const int k =
            std::min(bands - 1, static_cast<int>((bins[i].temp_c - lo) / (hi - lo) * bands));
        temp[static_cast<size_t>(k)].rows.push_back(static_cast<Index>(i));
    }
    for (WindowSpec& w : temp) {
        w.tau_s = static_cast<double>(w.rows.size()) * b.bin_s();
        if (w.rows.size() >= 3) out.push_back(std::move(w));
    }
    return out;
}

// The windows' statistic on one vector, given its residual r (the design projected out):
// plug-in, each window's |mean|; studentised, that over the Allan deviation at the window's tau
// of the noise model measured on r itself (as MakeSurrogates measures the run's), NaN where that
// is not positive.
std::vector<double> Statistic(const BinnedRun& b, const WindowStats& stats, const VectorXd& r,
                              WindowStatistic kind, std::vector<double>* ms) {
    std::vector<double> a = stats.EvaluateResidual(r, ms);
    if (kind == WindowStatistic::kPlugin) return a;
    const double floor_v = NoiseFloor(b.bins(), r).offset_rms_v;
    const NoiseModel m = MeasureAllanTerms(b.bins(), r, b.bin_s(), floor_v);
    for (size_t w = 0; w < a.size(); ++w) {
        const double avar = m.Avar(b.bin_s(), stats.windows()[w].tau_s);
        a[w] = avar > 0 ? a[w] / std::sqrt(avar) : NAN;
    }
    return a;
}

}  // namespace

std::vector<WindowExcess> WindowsAbove(const BinnedRun& b, const Eigen::MatrixXd& x_all,
                                       const Surrogates& s, const AnalysisOptions& o,
                                       double* threshold_out) {
    std::vector<WindowExcess> out;
    if (b.size() < 3 || s.noise.empty()) return out;
    const WindowStats stats(x_all, Windows(b));
    std::vector<std::vector<double>> null;
    std::vector<double> mean(stats.windows().size(), 0.0);
    std::vector<double> ms;
    for (const VectorXd& u : s.noise) {
        null.push_back(Statistic(b, stats, stats.Residual(u), o.window_statistic, &ms));
        for (size_t w = 0; w < mean.size(); ++w) mean[w] += ms[w] / s.noise.size();
    }
    const MaxTNull max_t(null);
    const double threshold = max_t.Threshold(o.window_fpr);
    if (threshold_out) *threshold_out = threshold;
    VectorXd y(static_cast<Index>(b.size()));
    for (size_t i = 0; i < b.size(); ++i) y[static_cast<Index>(i)] = b.bins()[i].gyro_v;
    const std::vector<double> run = Statistic(b, stats, stats.Residual(y), o.window_statistic, &ms);
    for (size_t w = 0; w < run.size(); ++w) {
        const double z = max_t.Z(w, run[w]);
        if (!(z > threshold)) continue;
        const WindowSpec& spec = stats.windows()[w];
        out.push_back({spec.where, std::sqrt(ms[w]), std::sqrt(mean[w]), z,
                       static_cast<int>(spec.rows.size())});
    }
    std::sort(out.begin(), out.end(),
              [](const WindowExcess& a, const WindowExcess& c) { return a.z > c.z; });
    return out;
}

namespace {

// mean over the surrogates of |P a|^2 / n, P the projection on x's columns (a column-pivoting QR:
// a column that adds nothing is left out of the projection, not an error).
double MeanProjected(const Eigen::MatrixXd& x, const std::vector<VectorXd>& noise) {
    if (x.cols() == 0 || noise.empty()) return 0.0;
    const Eigen::MatrixXd q = numeric::OrthonormalBasis(x);
    double s = 0.0;
    for (const VectorXd& a : noise) s += (q.transpose() * a).squaredNorm();
    return s / static_cast<double>(noise.size()) / static_cast<double>(x.rows());
}

}  // namespace

Transfer TransferOnSurrogates(const Eigen::MatrixXd& x_all, const std::vector<VectorXd>& noise,
                              const std::vector<std::vector<Index>>& groups, double max_ratio) {
    Transfer t;
    const size_t n = noise.size();
    if (n < 2 || x_all.rows() < 2 || x_all.cols() == 0 || !x_all.allFinite()) return t;
    const Eigen::MatrixXd q = numeric::OrthonormalBasis(x_all);
    const auto rows = static_cast<double>(x_all.rows());
    double model = 0.0, truth = 0.0;
    int miss = 0;
    for (size_t j = 0; j < n; ++j) {
        const VectorXd& a = noise[j];
        const VectorXd& b = noise[(j + 1) % n];
        const VectorXd pa = q * (q.transpose() * a);
        model += pa.squaredNorm() / rows;
        truth += b.squaredNorm() / rows;
        const double bb = b.squaredNorm();
        if (bb > 0.0 && (b - pa).squaredNorm() > max_ratio * max_ratio * bb) ++miss;
    }
    model /= static_cast<double>(n), truth /= static_cast<double>(n);
    if (!(truth > 0.0)) return t;
    t.model_rms_v = std::sqrt(model);
    t.truth_rms_v = std::sqrt(truth);
    t.ratio = std::sqrt(1.0 + model / truth);
    t.miss_fraction = static_cast<double>(miss) / static_cast<double>(n);
    for (const std::vector<Index>& g : groups) {
        std::vector<Index> keep;
        for (Index c = 0; c < x_all.cols(); ++c)
            if (std::find(g.begin(), g.end(), c) == g.end()) keep.push_back(c);
        const double without = MeanProjected(x_all(Eigen::all, keep), noise);
        t.group_adds_v.push_back(std::sqrt(std::max(0.0, model - without)));
    }
    return t;
}

// Step 9's transfer check (evidence.hpp, TransferOnSurrogates): the extended model's columns on
// all bins, grouped as the declared terms and one group per added effect.
void TransferCheck(const MatrixXd& base, const std::vector<std::string>& terms,
                   const std::vector<VectorXd>& noise, const AnalysisOptions& o,
                   SensorResult& res) {
    std::vector<std::vector<Index>> groups(1);
    std::vector<std::string> names = {"declared"};
    for (size_t k = 0; k < terms.size(); ++k) {
        const auto it = std::find_if(res.added.begin(), res.added.end(),
                                     [&](const AddedEffect& a) { return a.term == terms[k]; });
        if (it == res.added.end()) {
            groups[0].push_back(static_cast<Index>(k));
            continue;
        }
        const auto g = std::find(names.begin(), names.end(), it->effect);
        if (g != names.end()) {
            groups[static_cast<size_t>(g - names.begin())].push_back(static_cast<Index>(k));
        } else {
            names.push_back(it->effect);
            groups.push_back({static_cast<Index>(k)});
        }
    }
    const Transfer t = TransferOnSurrogates(base, noise, groups,
                                            o.max_transfer_ratio > 0
                                                ? o.max_transfer_ratio
                                                : AnalysisOptions::Defaults().max_transfer_ratio);
    res.transfer_model_rms_v = t.model_rms_v;
    res.transfer_truth_rms_v = t.truth_rms_v;
    res.transfer_ratio = t.ratio;
    res.transfer_miss_fraction = t.miss_fraction;
    res.transfer_term.clear();
    res.transfer_term_rms_v = kNan;
    for (size_t g = 0; g < t.group_adds_v.size(); ++g)
        if (!(t.group_adds_v[g] <= res.transfer_term_rms_v))
            res.transfer_term = names[g], res.transfer_term_rms_v = t.group_adds_v[g];
}

}  // namespace gyrocal::analysis::detail
