#include "processors/analysis/selection.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "lcmtypes/text/number.hpp"
#include "processors/analysis/regress.hpp"
#include "processors/analysis/steps.hpp"
#include "processors/model/terms.hpp"
#include "processors/numeric/least_squares.hpp"

namespace gyrocal::analysis::detail {

using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::VectorXd;

namespace {

struct Encompassing {
    double z2_best = 0.0, z2_other = 0.0;
};

// Both columns in the model at once: each one's z^2 with the robust covariance, the noise taken
// from the model with all remaining candidates (as in the forward steps) when there is one.
Encompassing Encompass(const Context& c, const MatrixXd& x, const VectorXd& best,
                       const VectorXd& other, const VectorXd* noise, int noise_params) {
    MatrixXd xe(x.rows(), x.cols() + 2);
    xe << x, best, other;
    const LsFit f = FitLs(xe, c.y, c.segment, c.hac_lag, noise, noise_params);
    if (!f.ok) return {};
    const Index i = x.cols();
    return {f.coeffs[i] * f.coeffs[i] / f.covariance(i, i),
            f.coeffs[i + 1] * f.coeffs[i + 1] / f.covariance(i + 1, i + 1)};
}

// A collinear pair judged together: both columns added at once, (a) the joint Wald statistic
// c' V^-1 c of their two coefficients (robust covariance, the same noise as the forward steps),
// (b) the blocked-CV gain of the pair, (c) the size of what the pair adds after projecting out the
// model. The data may not say WHICH of the two carries an effect and still say that the pair
// predicts data it did not see.
struct JointScore {
    double z2 = 0.0, cv_gain = 0.0, effect_rms_v = 0.0;
    double z2_a = 0.0, z2_b = 0.0;  // each coefficient alone, with the other in the model
    bool ok = false;
};
JointScore Joint(const Context& c, const MatrixXd& x, double base_cv, const VectorXd& a,
                 const VectorXd& b, const VectorXd* noise, int noise_params) {
    JointScore j;
    MatrixXd xe(x.rows(), x.cols() + 2);
    xe << x, a, b;
    const LsFit f = FitLs(xe, c.y, c.segment, c.hac_lag, noise, noise_params);
    if (!f.ok) return j;
    const Index i = x.cols();
    const Eigen::Vector2d cf = f.coeffs.segment<2>(i);
    const Eigen::Matrix2d v = f.covariance.block<2, 2>(i, i);
    const Eigen::LDLT<Eigen::Matrix2d> ldlt(v);
    if (ldlt.info() != Eigen::Success) return j;
    j.z2 = cf.dot(ldlt.solve(cf));
    j.z2_a = cf[0] * cf[0] / v(0, 0);
    j.z2_b = cf[1] * cf[1] / v(1, 1);
    const double cv = BlockedCvMse(xe, c.y, c.cv_blocks, c.cv_guard);
    if (!std::isfinite(cv) || !(base_cv > 0.0)) return j;
    j.cv_gain = (base_cv - cv) / base_cv;
    const VectorXd pred = numeric::ProjectOut(x, xe.rightCols(2)) * cf;
    j.effect_rms_v = pred.norm() / std::sqrt(static_cast<double>(pred.size()));
    j.ok = std::isfinite(j.z2);
    return j;
}

// (a)-(c) for the pair, and each member determined on its own with the other in
// (min_pair_member_z2): a pair whose split between the two is arbitrary (near-perfect
// collinearity) predicts this run but puts an arbitrary split into any run where the two
// regressors differ.
bool PairPasses(const JointScore& j, const Floor& floor, const AnalysisOptions& o) {
    const bool big_enough = !std::isfinite(floor.offset_rms_v) ||
                            j.effect_rms_v > o.min_effect_floor_ratio * floor.offset_rms_v;
    const bool split_known = j.z2_a > o.min_pair_member_z2 && j.z2_b > o.min_pair_member_z2;
    return j.ok && j.z2 > o.min_z2 && j.cv_gain > o.min_cv_gain && big_enough && split_known;
}

// (a)-(c) for the pair, whatever the split between its members.
bool PredictsAsPair(const JointScore& j, const Floor& floor, const AnalysisOptions& o) {
    const bool big_enough = !std::isfinite(floor.offset_rms_v) ||
                            j.effect_rms_v > o.min_effect_floor_ratio * floor.offset_rms_v;
    return j.ok && j.z2 > o.min_z2 && j.cv_gain > o.min_cv_gain && big_enough;
}

std::string JointNote(const std::string& other, double r, const JointScore& j,
                      const std::string& separation) {
    return "added jointly with " + other + " (projected correlation " + text::Sig(r, 3) +
           "; together z2 " + text::Sig(j.z2, 3) + ", cv_gain " + text::Sig(j.cv_gain, 2) +
           "): this data cannot say which of the two carries the effect; to separate: " +
           separation;
}

// The forward selection's state: the model so far (terms and their design on the training
// bins), the candidates still in the pool and every tested candidate's latest statistics.
struct Forward {
    Forward(const Context& c_, std::vector<Candidate> pool_, const Floor& floor_,
            const AnalysisOptions& o_)
        : c(c_), floor(floor_), o(o_), pool(std::move(pool_)) {
        sel.terms = o.offset_terms;
        x = c.Design(sel.terms);
    }
    const Context& c;
    const Floor& floor;
    const AnalysisOptions& o;
    std::vector<Candidate> pool;
    Selection sel;
    std::map<std::string, CandidateResult> last;  // latest statistics of each pool candidate
    std::vector<std::string> joint;  // effects added as a collinear pair (re-tested as a pair)
    // Columns (training rows) of a collinear pair dropped as ambiguous that predicts data it did
    // not see as a pair: fitted with the terms while the other candidates are tested, never kept.
    MatrixXd aside;
    MatrixXd x;  // design of sel.terms, then any nuisance columns, then `aside`
    // Candidate::last_resort, until the effect it competes after is in the model.
    bool LastResort(const Candidate& cand) const {
        return cand.last_resort && std::find(sel.added_effects.begin(), sel.added_effects.end(),
                                             cand.competes_after) == sel.added_effects.end();
    }
    // Candidate::on_rate_tracker: while the model has a term on the rate tracker (thermometer_lag:
    // dTdt or dT*dTdt; temp_rate: dT*dTdt), the candidate's term at that term's time constant
    // only; otherwise its own grid (`free`, the pool's grids as OffsetCandidates made them).
    std::map<std::string, std::vector<std::string>> free;
    void TieToRateTracker() {
        double product_tau = kNan, any_tau = kNan;
        for (const std::string& t : sel.terms) {
            model::ResolvedTerm r;
            if (!model::ResolveTerm(t, &r, nullptr)) continue;
            const double tau = r.c.param > 0.0 ? r.c.param : GYROCAL_DEFAULT_RATE_TAU_S;
            if (r.c.kind == GYROCAL_TERM_DT_DTDT && std::isnan(product_tau)) product_tau = tau;
            if ((r.c.kind == GYROCAL_TERM_DTDT || r.c.kind == GYROCAL_TERM_DT_DTDT) &&
                std::isnan(any_tau))
                any_tau = tau;
        }
        for (Candidate& cand : pool) {
            if (!cand.on_rate_tracker) continue;
            if (!free.count(cand.effect)) free[cand.effect] = cand.grid;
            const bool product = cand.effect == "thermometer_lag";
            const double tau = product ? any_tau : product_tau;
            cand.grid = free[cand.effect];
            if (std::isnan(tau)) continue;
            cand.grid = {product ? model::LagProductTerm(tau) : model::RateTerm(tau)};
        }
    }
    MatrixXd Design() const {
        const MatrixXd d = c.Design(sel.terms);
        if (aside.cols() == 0) return d;
        MatrixXd x2(d.rows(), d.cols() + aside.cols());
        x2 << d, aside;
        return x2;
    }
};

// Every pool candidate's statistics at one forward step, with the noise they were tested against.
struct StepScores {
    double base_cv = kNan;
    std::vector<StepScore> scores;  // in pool order
    std::vector<bool> passes;       // (a)-(c) all pass
    LsFit full;                     // the model with every remaining candidate in
    int noise_params = 0;           // its columns
    int best = -1;                  // the passing candidate that explains the most; -1: none
    const VectorXd* noise() const { return full.ok ? &full.residuals : nullptr; }
};

// The size for (c) of a term on the rate tracker whose partner is in the model (thermometer_lag
// beside a rate term, temp_rate beside a dT*dTdt): a lagging thermometer is ONE effect, f'(T) L
// dT/dt, whose first part (o1 L dT/dt) the rate term carries and whose second (2 o2 L dT dT/dt)
// the product; its size is what both columns together add to the model without the partner
// (fitted with the candidate, projected out of the other terms). Either part alone is a fraction
// of the lag's size on many runs (the floor of one 10 s bin is the yardstick of (c), and a
// systematic 50 uV over the ramps is 10-40 deg/h of held-out drift), so judged alone it would
// never join its partner however strong its z^2 and CV gain; (a) and (b) still judge the
// candidate's own coefficient and prediction. Without its partner in the model: its own size.
double LagEffectRms(const Forward& f, const Candidate& cand, const StepScore& sc) {
    const int partner_kind =
        cand.effect == "thermometer_lag" ? GYROCAL_TERM_DTDT : GYROCAL_TERM_DT_DTDT;
    Index partner = -1;
    for (size_t j = 0; j < f.sel.terms.size() && partner < 0; ++j) {
        model::ResolvedTerm r;
        if (model::ResolveTerm(f.sel.terms[j], &r, nullptr) && r.c.kind == partner_kind)
            partner = static_cast<Index>(j);
    }
    if (partner < 0 || sc.column.size() == 0) return sc.effect_rms_v;
    MatrixXd xe(f.x.rows(), f.x.cols() + 1);
    xe << f.x, sc.column;
    const LsFit fit = FitLs(xe, f.c.y, f.c.segment, 0);
    if (!fit.ok) return sc.effect_rms_v;
    MatrixXd others(f.x.rows(), f.x.cols() - 1);
    others << f.x.leftCols(partner), f.x.rightCols(f.x.cols() - partner - 1);
    MatrixXd both(f.x.rows(), 2);
    both << f.x.col(partner), sc.column;
    const VectorXd lag = numeric::ProjectOut(others, both) *
                         Eigen::Vector2d(fit.coeffs[partner], fit.coeffs[f.x.cols()]);
    return lag.norm() / std::sqrt(static_cast<double>(lag.size()));
}

// Records a candidate's statistics at this step (rejected until something decides otherwise) and
// says whether it passes (a) z^2, (b) the blocked-CV gain and (c) its size above the floor.
bool Passes(const StepScore& s, const Candidate& cand, int step, const Floor& floor,
            const AnalysisOptions& o, CandidateResult& r) {
    r = {cand.effect, s.term, Decision::kRejected, s.z2, s.cv_gain, step, "", s.effect_rms_v};
    r.grid_edge = s.grid_edge;
    if (!s.ok) r.note = "could not be fitted with the current model";
    const bool big_enough = !std::isfinite(floor.offset_rms_v) ||
                            s.effect_rms_v > o.min_effect_floor_ratio * floor.offset_rms_v;
    if (s.ok && !big_enough)
        r.note = "effect RMS " + text::Sig(s.effect_rms_v, 3) + " V is below " +
                 text::Sig(o.min_effect_floor_ratio, 3) + "x the noise floor " +
                 text::Sig(floor.offset_rms_v, 3) + " V";
    return s.ok && s.z2 > o.min_z2 && s.cv_gain > o.min_cv_gain && big_enough;
}

StepScores ScoreStep(Forward& f, int step) {
    const Context& c = f.c;
    StepScores s;
    s.base_cv = BlockedCvMse(f.x, c.y, c.cv_blocks, c.cv_guard);
    // First pass: each candidate's column (warm-up tau searched). The noise for the tests is the
    // residual of the model with ALL remaining candidates in (when it can be fitted), so a second
    // missing effect does not pass for noise while the first is tested.
    MatrixXd xfull = f.x;
    f.TieToRateTracker();
    for (size_t k = 0; k < f.pool.size(); ++k) {
        s.scores.push_back(Score(c, f.x, s.base_cv, f.pool[k], f.o));
        if (s.scores.back().column.size() == 0 || f.LastResort(f.pool[k])) continue;
        MatrixXd xn(xfull.rows(), xfull.cols() + 1);
        xn << xfull, s.scores.back().column;
        xfull = xn;
    }
    s.full = FitLs(xfull, c.y, c.segment, 0);
    s.noise_params = static_cast<int>(xfull.cols());
    s.passes.assign(f.pool.size(), false);
    for (size_t k = 0; k < f.pool.size(); ++k) {
        if (f.LastResort(f.pool[k]) && s.scores[k].column.size() > 0) {
            // Its own noise: the others' model with its column in too (left out of theirs).
            MatrixXd xk(xfull.rows(), xfull.cols() + 1);
            xk << xfull, s.scores[k].column;
            const LsFit own = FitLs(xk, c.y, c.segment, 0);
            if (own.ok)
                s.scores[k] = Score(c, f.x, s.base_cv, f.pool[k], f.o, &own.residuals,
                                    static_cast<int>(xk.cols()));
        } else if (s.noise()) {
            s.scores[k] = Score(c, f.x, s.base_cv, f.pool[k], f.o, s.noise(), s.noise_params);
        }
        if (f.pool[k].on_rate_tracker)
            s.scores[k].effect_rms_v = LagEffectRms(f, f.pool[k], s.scores[k]);
        s.passes[k] = Passes(s.scores[k], f.pool[k], step, f.floor, f.o, f.last[f.pool[k].effect]);
        // The best explains the most (smallest residual sum of squares), not the largest z^2: a
        // candidate correlated with a stronger missing effect borrows its signal.
        if (s.passes[k] && !f.LastResort(f.pool[k]) &&
            (s.best < 0 || s.scores[k].rss < s.scores[static_cast<size_t>(s.best)].rss))
            s.best = static_cast<int>(k);
    }
    // A last resort only when no other candidate passes.
    for (size_t k = 0; k < f.pool.size() && s.best < 0; ++k)
        if (s.passes[k] && f.LastResort(f.pool[k])) s.best = static_cast<int>(k);
    return s;
}

// Collinear candidates: with both in the model the data may still say which (an encompassing
// test): the one that keeps its significance while the other loses it explains the other. When
// the best by RSS loses to a twin, the twin is taken instead and its twins are examined in turn
// (at most once per candidate). Returns the candidate to add and, in `twins`, those the data
// cannot tell from it.
size_t WinnerAmongTwins(Forward& f, const StepScores& s, std::vector<size_t>& twins) {
    auto b = static_cast<size_t>(s.best);
    std::vector<bool> was_best(f.pool.size(), false);
    for (bool again = true; again;) {
        again = false;
        was_best[b] = true;
        twins.clear();
        for (size_t k = 0; k < f.pool.size(); ++k) {
            // A last resort is in contention only when it is the best (nothing else passes).
            if (k == b || s.scores[k].column.size() == 0 || f.LastResort(f.pool[k])) continue;
            const double r = ProjectedCorrelation(f.x, s.scores[b].column, s.scores[k].column);
            if (!std::isfinite(r) || std::fabs(r) <= f.o.max_collinearity) continue;
            const Encompassing e = Encompass(f.c, f.x, s.scores[b].column, s.scores[k].column,
                                             s.noise(), s.noise_params);
            if (e.z2_best > f.o.min_z2) {
                const std::string& best = f.pool[b].effect;
                const std::string& other = f.pool[k].effect;
                f.last[other].note = "collinear with " + best + " (projected correlation " +
                                     text::Sig(r, 3) + "); with both in the model " + best +
                                     " keeps z2 " + text::Sig(e.z2_best, 3) + ", " + other + " " +
                                     text::Sig(e.z2_other, 3);
                continue;
            }
            if (e.z2_other > f.o.min_z2 && !was_best[k] && s.passes[k]) {
                b = k;  // the twin explains the best: examine it instead
                again = true;
                break;
            }
            twins.push_back(k);
        }
    }
    return b;
}

// One collinear pair (b and its only twin k): both added when the pair passes (a)-(c) jointly
// and each member is determined with the other in; j: the pair's joint score, for the caller.
bool AddedAsPair(Forward& f, const StepScores& s, size_t b, size_t k, JointScore& j) {
    // Two terms on the rate tracker at two time constants cannot be one coefficient set's.
    if (f.pool[b].on_rate_tracker && f.pool[k].on_rate_tracker &&
        ParamOf(s.scores[b].term) != ParamOf(s.scores[k].term))
        return false;
    j = Joint(f.c, f.x, s.base_cv, s.scores[b].column, s.scores[k].column, s.noise(),
              s.noise_params);
    if (!PairPasses(j, f.floor, f.o)) return false;
    const double r = ProjectedCorrelation(f.x, s.scores[b].column, s.scores[k].column);
    for (size_t i : {b, k}) {
        CandidateResult& cr = f.last[f.pool[i].effect];
        cr.decision = Decision::kAdded;
        cr.note += (cr.note.empty() ? "" : "; ") +
                   JointNote(f.pool[i == b ? k : b].effect, r, j,
                             Separation(f.pool[b].effect, f.pool[k].effect));
    }
    f.sel.joint_pairs.push_back({f.pool[b].effect, f.pool[k].effect, f.sel.ambiguous.size()});
    f.sel.ambiguous.push_back(f.pool[b].effect + " vs " + f.pool[k].effect);
    for (size_t i : {b, k}) {
        f.sel.terms.push_back(s.scores[i].term);
        f.sel.added_effects.push_back(f.pool[i].effect);
        f.joint.push_back(f.pool[i].effect);
    }
    f.x = f.Design();
    f.pool.erase(f.pool.begin() + static_cast<long>(std::max(b, k)));
    f.pool.erase(f.pool.begin() + static_cast<long>(std::min(b, k)));
    return true;
}

// b and its twins are ambiguous, each with the measurement that would separate it from b: none of
// them is added, all leave the pool.
void DropAmbiguous(Forward& f, const StepScores& s, size_t b, const std::vector<size_t>& twins) {
    std::vector<size_t> drop = twins;
    drop.push_back(b);
    for (size_t k : twins) {
        const double r = ProjectedCorrelation(f.x, s.scores[b].column, s.scores[k].column);
        for (size_t i : {b, k}) {
            CandidateResult& cr = f.last[f.pool[i].effect];
            cr.decision = Decision::kAmbiguous;
            const std::string other = f.pool[i == b ? k : b].effect;
            cr.note += (cr.note.empty() ? "" : "; ") + std::string("ambiguous with ") + other +
                       " (projected correlation " + text::Sig(r, 3) +
                       "); to separate: " + Separation(f.pool[b].effect, f.pool[k].effect);
        }
        f.sel.ambiguous.push_back(f.pool[b].effect + " vs " + f.pool[k].effect);
    }
    std::sort(drop.rbegin(), drop.rend());
    for (size_t k : drop) f.pool.erase(f.pool.begin() + static_cast<long>(k));
}

// A pair that passes (a)-(c) jointly but whose split between its members the data do not
// determine (min_pair_member_z2): ambiguous, neither added, as DropAmbiguous; but the pair does
// predict data it did not see, so its columns are accounted for while the remaining candidates
// are tested (fitted with them, never kept: Forward::aside). Left in the residual, an effect of
// z2 in the tens would pass for noise and hide every smaller one behind it.
void SetAside(Forward& f, const StepScores& s, size_t b, size_t k, const JointScore& j) {
    for (size_t i : {b, k})
        f.last[f.pool[i].effect].note = "together with " + f.pool[i == b ? k : b].effect + " z2 " +
                                        text::Sig(j.z2, 3) + ", cv_gain " +
                                        text::Sig(j.cv_gain, 2) + ", each with the other in z2 " +
                                        text::Sig(i == b ? j.z2_a : j.z2_b, 3) +
                                        ": accounted for while the other candidates were tested";
    MatrixXd aside(f.x.rows(), f.aside.cols() + 2);
    aside << f.aside, s.scores[b].column, s.scores[k].column;
    f.aside = aside;
    DropAmbiguous(f, s, b, {k});
    f.x = f.Design();
}

void AddTerm(Forward& f, const StepScores& s, size_t b) {
    f.last[f.pool[b].effect].decision = Decision::kAdded;
    f.sel.terms.push_back(s.scores[b].term);
    f.sel.added_effects.push_back(f.pool[b].effect);
    f.x = f.Design();
    f.pool.erase(f.pool.begin() + static_cast<long>(b));
}

// Backward re-test: each added term with all the others in the model and the model's own
// residuals as the noise; the weakest below its threshold is removed, and so on. A term added
// alone is held to min_z2. A member of a pair added jointly is collinear with its partner by
// construction (each alone has a wide variance with the other in): it entered because the pair
// passed and each member was determined with the other in (min_pair_member_z2), and it is held
// to that same criterion with everything added after it in the model too. A later term may take
// what made the split known (on a profile that ramps down once, the thermometer_lag product
// takes the residual curvature against which a rate term and a heating branch were told apart):
// the member below min_pair_member_z2 then goes, its partner stays as a term alone (held to
// min_z2 from then on), and the pair's "a vs b" entry says which was kept and which was not
// attributed (JointPairFates).
void RemoveWeakTerms(Forward& f) {
    const size_t nd = f.o.offset_terms.size();
    for (;;) {
        const LsFit fit = FitLs(f.x, f.c.y, f.c.segment, f.c.hac_lag);
        if (!fit.ok || f.sel.terms.size() == nd) break;
        size_t weakest = 0;
        double weakest_z2 = INFINITY, weakest_margin = INFINITY;
        bool weakest_joint = false;
        for (size_t k = nd; k < f.sel.terms.size(); ++k) {
            const std::string& e = f.sel.added_effects[k - nd];
            const bool joint = std::find(f.joint.begin(), f.joint.end(), e) != f.joint.end();
            const auto i = static_cast<Index>(k);
            const double z2 = fit.coeffs[i] * fit.coeffs[i] / fit.covariance(i, i);
            const double margin = z2 / (joint ? f.o.min_pair_member_z2 : f.o.min_z2);
            if (margin < weakest_margin)
                weakest_margin = margin, weakest_z2 = z2, weakest = k, weakest_joint = joint;
        }
        if (!(weakest_margin < 1.0)) break;
        const std::string effect = f.sel.added_effects[weakest - nd];
        std::string others;
        for (const std::string& e : f.sel.added_effects)
            if (e != effect) others += (others.empty() ? "" : ", ") + e;
        CandidateResult& r = f.last[effect];
        r.decision = Decision::kRejected;
        r.z2 = weakest_z2;
        r.note +=
            std::string(r.note.empty() ? "" : "; ") + "removed on re-test with " + others +
            " in the model (z2 " + text::Sig(weakest_z2, 3) +
            (weakest_joint ? ", below min_pair_member_z2 " + text::Sig(f.o.min_pair_member_z2, 3) +
                                 ": the pair's split is no longer determined)"
                           : ")");
        if (weakest_joint) {
            // Its partner stays as a term alone.
            for (const Selection::JointPair& p : f.sel.joint_pairs) {
                if (p.a != effect && p.b != effect) continue;
                const std::string& partner = p.a == effect ? p.b : p.a;
                f.joint.erase(std::remove(f.joint.begin(), f.joint.end(), partner), f.joint.end());
            }
            f.joint.erase(std::remove(f.joint.begin(), f.joint.end(), effect), f.joint.end());
        }
        f.sel.terms.erase(f.sel.terms.begin() + static_cast<long>(weakest));
        f.sel.added_effects.erase(f.sel.added_effects.begin() + static_cast<long>(weakest - nd));
        f.x = f.Design();
    }
}

}  // namespace

Selection SelectOffsetTerms(const Context& c, std::vector<Candidate> pool, const Floor& floor,
                            const AnalysisOptions& o) {
    Forward f(c, std::move(pool), floor, o);
    for (int step = 1; !f.pool.empty(); ++step) {
        const StepScores s = ScoreStep(f, step);
        if (s.best < 0) break;
        std::vector<size_t> twins;
        const size_t b = WinnerAmongTwins(f, s, twins);
        JointScore j;
        if (twins.size() == 1 && AddedAsPair(f, s, b, twins[0], j)) continue;
        if (twins.empty()) {
            AddTerm(f, s, b);
        } else if (twins.size() == 1 && PredictsAsPair(j, f.floor, f.o)) {
            SetAside(f, s, b, twins[0], j);
        } else {
            DropAmbiguous(f, s, b, twins);
        }
    }
    RemoveWeakTerms(f);
    for (auto& [effect, r] : f.last) f.sel.candidates.push_back(r);
    f.sel.x = c.Design(f.sel.terms);
    return std::move(f.sel);
}

}  // namespace gyrocal::analysis::detail
