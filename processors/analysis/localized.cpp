#include "processors/analysis/localized.hpp"

#include <cmath>
#include <cstdlib>

#include "lcmtypes/text/number.hpp"
#include "processors/analysis/heldout.hpp"
#include "processors/analysis/null.hpp"
#include "processors/analysis/regress.hpp"
#include "processors/analysis/residual.hpp"
#include "processors/numeric/least_squares.hpp"

namespace gyrocal::analysis::detail {

using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::VectorXd;

namespace {

double TauOf(const std::string& term) {
    const size_t open = term.find('(');
    return open == std::string::npos ? kNan : std::strtod(term.c_str() + open + 1, nullptr);
}

// (a) and (c) of the chosen term with the base model, on all bins.
void SizeAndZ2(const Context& all, const MatrixXd& base, const VectorXd& col, LocalizedCheck& c) {
    MatrixXd x(base.rows(), base.cols() + 1);
    x << base, col;
    const LsFit f = FitLs(x, all.y, all.segment, all.hac_lag);
    if (!f.ok) return;
    const Index p = base.cols();
    c.z2 = f.coeffs[p] * f.coeffs[p] / f.covariance(p, p);
    const VectorXd proj = numeric::ProjectOut(base, col);
    c.effect_rms_v =
        std::fabs(f.coeffs[p]) * proj.norm() / std::sqrt(static_cast<double>(proj.size()));
}

// A linear drift in time [h] on all bins.
VectorXd DriftColumn(const BinnedRun& binned) {
    const std::vector<Bin>& bins = binned.bins();
    VectorXd t_h(static_cast<Index>(bins.size()));
    for (size_t i = 0; i < bins.size(); ++i)
        t_h[static_cast<Index>(i)] = 1e-6 * (bins[i].mid_utime - bins.front().mid_utime) / 3600.0;
    return t_h;
}

// The held-out residuals of base (r0) and of base with col (r1), both fitted on train.
bool HeldPair(const MatrixXd& base, const VectorXd& col, const VectorXd& y,
              const std::vector<Index>& train, const std::vector<Index>& held, VectorXd& r0,
              VectorXd& r1) {
    Family f{"", "", "", "", "", {}, {}, false};
    f.cols.push_back(col);
    const HeldOutSearch search(base, train, held, {f});
    if (!search.ok()) return false;
    const FamilyFit fit = search.Evaluate(y, true).at(0);
    if (fit.best < 0) return false;
    r0 = fit.r0, r1 = fit.r1;
    return true;
}

bool Improves(const Gain& g, const AnalysisOptions& o) {
    return std::isfinite(g.z) && g.z > o.gate_min_z && g.mean_v2 > 0.0;
}

// The drift rule (header) for the warm-up column w on the localized split.
void DriftRule(const BinnedRun& binned, const Context& all, const MatrixXd& base, const VectorXd& w,
               const std::vector<Index>& train, const std::vector<Index>& held,
               const AnalysisOptions& o, LocalizedCheck& c) {
    const VectorXd y = BinValues(binned), d = DriftColumn(binned);
    MatrixXd with_d(base.rows(), base.cols() + 1);
    with_d << base, d;
    VectorXd r0, r_d, r_d2, r_wd;
    if (!HeldPair(base, d, y, train, held, r0, r_d) ||
        !HeldPair(with_d, w, y, train, held, r_d2, r_wd))
        return;
    c.drift_drop = 1.0 - r_d.squaredNorm() / r0.squaredNorm();
    std::vector<int> block;
    for (Index i : held)
        block.push_back(static_cast<int>(std::floor(
            binned.bins()[static_cast<size_t>(i)].time_since_power_s / o.early_block_s)));
    const bool warmup_adds = Improves(HeldOutGain(r_d2, r_wd, block, all.hac_lag), o);
    // Named only when it predicts its blocks better than the drift and still adds to it: with a
    // profile that only warms, the declared quadratic takes part of a drift and bends the rest,
    // which a warm-up then adds to (aging over monotonic setpoints, RigOutside). Said as a drift
    // when the drift predicts them at least as well; ambiguous when only the warm-up predicts
    // better.
    const bool better = c.drift_drop < c.drop;
    c.drift_rule = better && warmup_adds ? Decision::kAdded
                   : !better             ? Decision::kRejected
                                         : Decision::kAmbiguous;
}

// The step rule (header) for the warm-up column w on the localized split.
void StepRule(const BinnedRun& binned, const Context& all, const MatrixXd& base, const VectorXd& w,
              const std::vector<Index>& train, const std::vector<Index>& held,
              const AnalysisOptions& o, LocalizedCheck& c) {
    const VectorXd y = BinValues(binned);
    const Family step = StepFamily(binned.bins());
    if (step.grid.size() < 2) return;
    const HeldOutSearch search(base, train, held, {step});
    if (!search.ok()) return;
    const FamilyFit s = search.Evaluate(y, true).at(0);
    if (s.best < 0) return;
    c.step_s = step.grid[static_cast<size_t>(s.best)];
    c.step_drop = 1.0 - s.r1.squaredNorm() / s.r0.squaredNorm();
    MatrixXd with_s(base.rows(), base.cols() + 1);
    with_s << base, step.cols[static_cast<size_t>(s.best)];
    VectorXd r_s, r_ws;
    if (!HeldPair(with_s, w, y, train, held, r_s, r_ws)) return;
    std::vector<int> block;
    for (Index i : held)
        block.push_back(static_cast<int>(std::floor(
            binned.bins()[static_cast<size_t>(i)].time_since_power_s / o.early_block_s)));
    const bool warmup_adds = Improves(HeldOutGain(r_s, r_ws, block, all.hac_lag), o);
    const bool better = c.step_drop < c.drop;
    c.step_rule = better && warmup_adds ? Decision::kAdded
                  : !better             ? Decision::kRejected
                                        : Decision::kAmbiguous;
}

}  // namespace

LocalizedCheck CheckWarmup(const BinnedRun& binned, const Context& all,
                           const std::vector<std::string>& base_terms, const Candidate& warmup,
                           const Surrogates& s, const AnalysisOptions& o) {
    LocalizedCheck c;
    if (!warmup.why_not.empty() || warmup.grid.empty()) {
        c.note = warmup.why_not;
        return c;
    }
    c.support_s = 3.0 * TauOf(warmup.grid.back());
    std::vector<Index> train, held;
    int support_train = 0;
    for (size_t i = 0; i < binned.size(); ++i) {
        const double t_on = binned.bins()[i].time_since_power_s;
        const bool inside = t_on < c.support_s;
        const bool odd = static_cast<long>(std::floor(t_on / o.early_block_s)) % 2 == 1;
        (inside && odd ? held : train).push_back(static_cast<Index>(i));
        support_train += inside && !odd;
    }
    c.n_held = static_cast<int>(held.size());
    if (held.size() < 3 || support_train < 3) {
        c.note = "too few still bins in the first " + text::Sig(c.support_s, 3) +
                 " s after power-on to hold some out (" + std::to_string(held.size()) + " held, " +
                 std::to_string(support_train) + " for training)";
        return c;
    }
    Family fam{"warmup", "time since power-on", "", " s", "tau", {}, {}, false};
    for (const std::string& t : warmup.grid)
        fam.grid.push_back(TauOf(t)), fam.cols.push_back(binned.Column(t, all.t0));
    const MatrixXd base = all.AllDesign(base_terms);
    const HeldOutSearch search(base, train, held, {fam});
    if (!search.ok()) return c;
    const NullVerdict v = JudgeOnNull(search, BinValues(binned), s.noise, o.warmup_fpr);
    const FamilyFit& f = v.fits.at(0);
    if (f.best < 0) return c;
    c.tested = true;
    c.term = warmup.grid[static_cast<size_t>(f.best)];
    c.grid_edge = f.best == 0 || f.best + 1 == static_cast<int>(warmup.grid.size());
    c.p = v.p.at(0);
    c.drop = 1.0 - f.r1.squaredNorm() / f.r0.squaredNorm();
    SizeAndZ2(all, base, fam.cols[static_cast<size_t>(f.best)], c);
    const bool big_enough =
        !std::isfinite(s.floor_v) || c.effect_rms_v > o.min_effect_floor_ratio * s.floor_v;
    c.passes = c.p <= o.warmup_fpr && c.drop > 0.0 && c.z2 > o.min_z2 && big_enough;
    if (c.passes && f.best + 1 == static_cast<int>(warmup.grid.size())) {
        DriftRule(binned, all, base, fam.cols[static_cast<size_t>(f.best)], train, held, o, c);
        c.passes = !c.drift_rule || *c.drift_rule == Decision::kAdded;
    }
    if (c.passes) {
        StepRule(binned, all, base, fam.cols[static_cast<size_t>(f.best)], train, held, o, c);
        c.passes = !c.step_rule || *c.step_rule == Decision::kAdded;
    }
    c.note = "localized check on " + std::to_string(c.n_held) + " held-out bins in interleaved " +
             text::Sig(o.early_block_s, 3) + " s blocks of the first " + text::Sig(c.support_s, 3) +
             " s after power-on: removes " + text::Sig(100.0 * c.drop, 3) +
             " % of their squared residual, reached by " + text::Sig(100.0 * c.p, 2) + " % of " +
             std::to_string(s.noise.size()) +
             " surrogates of the run's noise (need <= " + text::Sig(100.0 * o.warmup_fpr, 2) +
             " %); z2 " + text::Sig(c.z2, 3) + ", size " + text::Sig(c.effect_rms_v, 3) + " V";
    if (std::isfinite(c.drift_drop))
        c.note += "; tau at the grid's largest: a linear drift in time removes " +
                  text::Sig(100.0 * c.drift_drop, 3) + " % of the same blocks' squared residual, " +
                  (*c.drift_rule == Decision::kAdded ? "the warm-up predicts better and adds to it"
                   : *c.drift_rule == Decision::kRejected ? "it predicts them at least as well"
                                                          : "neither is the better shape");
    if (std::isfinite(c.step_drop))
        c.note += "; a one-time step at " + text::Sig(c.step_s, 3) + " s from the start removes " +
                  text::Sig(100.0 * c.step_drop, 3) + " % of the same blocks' squared residual, " +
                  (*c.step_rule == Decision::kAdded ? "the warm-up predicts better and adds to it"
                   : *c.step_rule == Decision::kRejected ? "it predicts them at least as well"
                                                         : "neither is the better shape");
    return c;
}

}  // namespace gyrocal::analysis::detail
