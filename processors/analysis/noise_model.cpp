#include "processors/analysis/noise_model.hpp"

#include <algorithm>
#include <cmath>
#include <map>

#include "lcmtypes/text/number.hpp"
#include "processors/noise/allan.hpp"

namespace gyrocal::analysis::detail {

namespace {

// Allan variance at m bins of a unit-variance AR(1) sampled once per bin (coefficient phi):
// (Var(S) - Cov(S1, S2)) / m^2 with S a sum of m consecutive values, S1 and S2 adjacent sums.
double Ar1Avar(double phi, int64_t m) {
    double var = 0.0, cov = 0.0;
    for (int64_t l = -(m - 1); l <= m - 1; ++l) {
        const double w = static_cast<double>(m - std::llabs(l));
        var += w * std::pow(phi, static_cast<double>(std::llabs(l)));
        cov += w * std::pow(phi, static_cast<double>(std::llabs(m + l)));
    }
    return (var - cov) / static_cast<double>(m * m);
}

std::vector<std::vector<double>> Stretches(const std::vector<Bin>& bins, const Eigen::VectorXd& r) {
    std::vector<std::vector<double>> out;
    for (size_t i = 0; i < bins.size(); ++i) {
        if (i == 0 || bins[i].segment != bins[i - 1].segment) out.emplace_back();
        out.back().push_back(r[static_cast<Eigen::Index>(i)]);
    }
    return out;
}

double SpanS(const std::vector<Bin>& bins) {
    return bins.size() < 2 ? 0.0 : (bins.back().mid_utime - bins.front().mid_utime) * 1e-6;
}

}  // namespace

namespace {

// The Allan terms of the residual (MeasureNoise's fit), and what its note says of them.
struct TermsFit {
    noise::NoiseTerms terms;
    std::vector<int64_t> grid;
    size_t stretches = 0, kept = 0;
    std::string screened;
};

TermsFit FitResidualTerms(const std::vector<Bin>& bins, const Eigen::VectorXd& residual,
                          double bin_s) {
    TermsFit f;
    const std::vector<std::vector<double>> stretches = Stretches(bins, residual);
    size_t longest = 0;
    for (const auto& s : stretches) longest = std::max(longest, s.size());
    // Each stretch adds the taus up to a quarter of its length (an Allan estimate of one stretch
    // alone), from one bin to a quarter of the longest. When that gives fewer than three taus (N
    // and B need three points: bins merged to near the stretches' length, 40 s bins between turns
    // 300 s apart), every stretch of 4 bins or more adds the taus up to half its length, to 3
    // bins at least: pooled over the run's stretches there are terms enough, and the same N and B
    // are measured as with shorter bins.
    const bool short_stretches = longest < 12;
    const int64_t per_m = short_stretches ? 2 : 4;
    f.grid = noise::TauGrid(short_stretches ? 3 : static_cast<int64_t>(longest / 4));
    std::vector<noise::SegmentSums> sums;
    for (const auto& s : stretches)
        if (s.size() >= static_cast<size_t>(2 * per_m))
            sums.push_back(noise::SumSegment(s, bin_s, f.grid, per_m));
    const std::vector<noise::SegmentSums> kept =
        sums.size() >= 3 ? noise::ScreenSegments(sums, bin_s, f.grid, 0.01, f.screened) : sums;
    f.terms = noise::FitTerms(kept, bin_s, f.grid, bin_s);
    f.stretches = sums.size();
    f.kept = kept.size();
    return f;
}

// The fitted terms into m (white from N when fitted); false when they could not be fitted.
bool SetTerms(const noise::NoiseTerms& t, double bin_s, double floor_v, NoiseModel& m) {
    m.white_v2 = std::isfinite(floor_v) ? floor_v * floor_v : 0.0;
    if (!t.ok || !std::isfinite(floor_v) || !(floor_v > 0)) return false;
    auto sq = [](double x) { return std::isfinite(x) ? x * x : 0.0; };
    m.measured = true;
    m.white_v2 = sq(t.arw) / bin_s;
    m.flicker_v = std::isfinite(t.bias) ? t.bias : 0.0;
    m.rrw_v_rts = std::isfinite(t.rrw) ? t.rrw : 0.0;
    return true;
}

// The flicker level whose slow noise of a bin mean equals the floor (k = 1): what the surrogates
// carry when the terms cannot be fitted, so that the window and feature nulls are not stricter
// than the floor bound; 0 when the floor or the run's span gives none.
double FlickerGivingUnitK(const std::vector<Bin>& bins, double bin_s, double floor_v) {
    const double unit = noise::SlowNoiseVariance(1.0, 0.0, bin_s, SpanS(bins));
    return std::isfinite(floor_v) && floor_v > 0 && unit > 0 ? floor_v / std::sqrt(unit) : 0.0;
}

}  // namespace

NoiseModel MeasureNoise(const std::vector<Bin>& bins, const Eigen::VectorXd& residual, double bin_s,
                        double floor_v) {
    NoiseModel m;
    const TermsFit f = FitResidualTerms(bins, residual, bin_s);
    const noise::NoiseTerms& t = f.terms;
    if (!SetTerms(t, bin_s, floor_v, m)) {
        m.note = "the Allan terms of the residual could not be fitted (" + std::to_string(f.kept) +
                 " stretches long enough): slow noise assumed "
                 "as large as the floor (k = 1)";
        m.flicker_v = FlickerGivingUnitK(bins, bin_s, floor_v);
        if (m.flicker_v > 0) m.slow_v2 = floor_v * floor_v;
        return m;
    }
    m.arw_v_rthz = t.arw;
    m.arw_se = t.arw_se;
    m.flicker_se_v = t.bias_se;
    m.slow_v2 = noise::SlowNoiseVariance(m.flicker_v, m.rrw_v_rts, bin_s, SpanS(bins));
    m.k = std::sqrt(m.slow_v2) / floor_v;
    m.note = "Allan deviation of the residual over " + std::to_string(f.kept) + " of " +
             std::to_string(f.stretches) + " still stretches, " + text::Sig(bin_s, 3) + "-" +
             text::Sig(static_cast<double>(f.grid.back()) * bin_s, 3) + " s: N " +
             text::Sig(t.arw, 3) + " V/rtHz, B " + text::Sig(m.flicker_v, 3) + " V, K " +
             text::Sig(m.rrw_v_rts, 3) + " V/rts" + (f.screened.empty() ? "" : "; " + f.screened);
    return m;
}

NoiseModel MeasureAllanTerms(const std::vector<Bin>& bins, const Eigen::VectorXd& residual,
                             double bin_s, double floor_v) {
    NoiseModel m;
    if (!SetTerms(FitResidualTerms(bins, residual, bin_s).terms, bin_s, floor_v, m))
        m.flicker_v = FlickerGivingUnitK(bins, bin_s, floor_v);
    return m;
}

double NoiseModel::Avar(double bin_s, double tau_s) const {
    return white_v2 * bin_s / tau_s + flicker_v * flicker_v + rrw_v_rts * rrw_v_rts * tau_s / 3.0;
}

SurrogateNoise::SurrogateNoise(const NoiseModel& m, const std::vector<Bin>& bins, double bin_s) {
    for (const Bin& b : bins) t_s_.push_back((b.mid_utime - bins.front().mid_utime) * 1e-6);
    white_sd_ = std::sqrt(std::max(0.0, m.white_v2));
    rrw_ = m.rrw_v_rts;
    const double span = std::max(SpanS(bins), bin_s);
    for (double tau = bin_s; tau <= 3.0 * span; tau *= 3.0) ou_tau_s_.push_back(tau);
    if (!(m.flicker_v > 0.0) || ou_tau_s_.empty()) return;
    // Equal-variance components scaled so that the bank's Allan variance over the tau grid
    // matches B^2 in least squares.
    const std::vector<int64_t> grid =
        noise::TauGrid(std::max<int64_t>(1, static_cast<int64_t>(span / bin_s / 4)));
    double sa = 0.0, saa = 0.0;
    for (int64_t g : grid) {
        double a = 0.0;
        for (double tau : ou_tau_s_) a += Ar1Avar(std::exp(-bin_s / tau), g);
        sa += a, saa += a * a;
    }
    ou_sd_ = saa > 0 ? m.flicker_v * std::sqrt(sa / saa) : 0.0;
}

Eigen::VectorXd SurrogateNoise::Draw(std::mt19937_64& rng) const {
    std::normal_distribution<double> normal(0.0, 1.0);
    const auto n = static_cast<Eigen::Index>(t_s_.size());
    Eigen::VectorXd v(n);
    std::vector<double> ou(ou_tau_s_.size());
    for (double& x : ou) x = ou_sd_ * normal(rng);
    double walk = 0.0;
    for (Eigen::Index i = 0; i < n; ++i) {
        const double dt =
            i > 0 ? t_s_[static_cast<size_t>(i)] - t_s_[static_cast<size_t>(i - 1)] : 0.0;
        double x = white_sd_ * normal(rng);
        for (size_t j = 0; j < ou.size(); ++j) {
            if (i > 0) {
                const double phi = std::exp(-dt / ou_tau_s_[j]);
                ou[j] = phi * ou[j] + ou_sd_ * std::sqrt(1.0 - phi * phi) * normal(rng);
            }
            x += ou[j];
        }
        if (i > 0) walk += rrw_ * std::sqrt(dt) * normal(rng);
        v[i] = x + walk;
    }
    return v;
}

}  // namespace gyrocal::analysis::detail
