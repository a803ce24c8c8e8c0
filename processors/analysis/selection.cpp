#include "selection.hpp"

#include <algorithm>
#include <cmath>
#include <map>

#include "numeric/least_squares.hpp"
#include "regress.hpp"
#include "text/number.hpp"

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
    const VectorXd pred = fit::ProjectOut(x, xe.rightCols(2)) * cf;
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

std::string JointNote(const std::string& other, double r, const JointScore& j,
                      const std::string& separation) {
    return "added jointly with " + other + " (projected correlation " + text::Sig(r, 3) +
           "; together z2 " + text::Sig(j.z2, 3) + ", cv_gain " + text::Sig(j.cv_gain, 2) +
           "): this data cannot say which of the two carries the effect; to separate: " +
           separation;
}

}  // namespace

Selection SelectOffsetTerms(const Context& c, std::vector<Candidate> pool, const Floor& floor,
                            const AnalysisOptions& o) {
    Selection sel;
    std::vector<std::string>& terms = sel.terms;
    std::vector<std::string>& added_effects = sel.added_effects;
    std::vector<std::string>& ambiguous = sel.ambiguous;
    terms = o.offset_terms;
    std::map<std::string, CandidateResult> last;  // latest statistics of each pool candidate
    std::vector<std::string> joint;  // effects added as a collinear pair (re-tested as a pair)
    MatrixXd x = c.Design(terms);
    for (int step = 1; !pool.empty(); ++step) {
        const double base_cv = BlockedCvMse(x, c.y, c.cv_blocks, c.cv_guard);
        // First pass: each candidate's column (warm-up tau searched). The noise for the tests
        // is the residual of the model with ALL remaining candidates in (when it can be
        // fitted), so a second missing effect does not pass for noise while the first is
        // tested.
        std::vector<StepScore> scores;
        MatrixXd xfull = x;
        for (size_t k = 0; k < pool.size(); ++k) {
            scores.push_back(Score(c, x, base_cv, pool[k], o));
            if (scores.back().column.size() == 0) continue;
            MatrixXd xn(xfull.rows(), xfull.cols() + 1);
            xn << xfull, scores.back().column;
            xfull = xn;
        }
        const LsFit full = FitLs(xfull, c.y, c.segment, 0);
        const VectorXd* noise = full.ok ? &full.residuals : nullptr;
        int best = -1;
        std::vector<bool> passes(pool.size(), false);
        for (size_t k = 0; k < pool.size(); ++k) {
            if (noise)
                scores[k] = Score(c, x, base_cv, pool[k], o, noise, static_cast<int>(xfull.cols()));
            const StepScore& s = scores[k];
            CandidateResult& r = last[pool[k].effect];
            r = {pool[k].effect, s.term, Decision::kRejected, s.z2, s.cv_gain,
                 step,           "",     s.effect_rms_v};
            r.grid_edge = s.grid_edge;
            if (!s.ok) r.note = "could not be fitted with the current model";
            const bool big_enough = !std::isfinite(floor.offset_rms_v) ||
                                    s.effect_rms_v > o.min_effect_floor_ratio * floor.offset_rms_v;
            if (s.ok && !big_enough)
                r.note = "effect RMS " + text::Sig(s.effect_rms_v, 3) + " V is below " +
                         text::Sig(o.min_effect_floor_ratio, 3) + "x the noise floor " +
                         text::Sig(floor.offset_rms_v, 3) + " V";
            const bool pass = s.ok && s.z2 > o.min_z2 && s.cv_gain > o.min_cv_gain && big_enough;
            passes[k] = pass;
            // The best explains the most (smallest residual sum of squares), not the largest
            // z^2: a candidate correlated with a stronger missing effect borrows its signal.
            if (pass && (best < 0 || s.rss < scores[static_cast<size_t>(best)].rss))
                best = static_cast<int>(k);
        }
        if (best < 0) break;
        auto b = static_cast<size_t>(best);
        std::vector<size_t> twins;
        // Collinear candidates: with both in the model the data may still say which (an
        // encompassing test): the one that keeps its significance while the other loses it
        // explains the other. When the best by RSS loses to a twin, the twin is taken instead
        // and its twins are examined in turn (at most once per candidate).
        std::vector<bool> was_best(pool.size(), false);
        for (bool again = true; again;) {
            again = false;
            was_best[b] = true;
            twins.clear();
            for (size_t k = 0; k < pool.size(); ++k) {
                if (k == b || scores[k].column.size() == 0) continue;
                const double r = ProjectedCorrelation(x, scores[b].column, scores[k].column);
                if (!std::isfinite(r) || std::fabs(r) <= o.max_collinearity) continue;
                const Encompassing e = Encompass(c, x, scores[b].column, scores[k].column,
                                                 noise, static_cast<int>(xfull.cols()));
                if (e.z2_best > o.min_z2) {
                    CandidateResult& cr = last[pool[k].effect];
                    cr.note = "collinear with " + pool[b].effect + " (projected correlation " +
                              text::Sig(r, 3) + "); with both in the model " + pool[b].effect +
                              " keeps z2 " + text::Sig(e.z2_best, 3) + ", " + pool[k].effect + " " +
                              text::Sig(e.z2_other, 3);
                    continue;
                }
                if (e.z2_other > o.min_z2 && !was_best[k] && passes[k]) {
                    b = k;  // the twin explains the best: examine it instead
                    again = true;
                    break;
                }
                twins.push_back(k);
            }
        }
        if (twins.size() == 1) {
            // One collinear pair: kept together when the pair passes (a)-(c) jointly.
            const size_t k = twins[0];
            const JointScore j = Joint(c, x, base_cv, scores[b].column, scores[k].column, noise,
                                       static_cast<int>(xfull.cols()));
            if (PairPasses(j, floor, o)) {
                const double r = ProjectedCorrelation(x, scores[b].column, scores[k].column);
                for (size_t i : {b, k}) {
                    CandidateResult& cr = last[pool[i].effect];
                    cr.decision = Decision::kAdded;
                    cr.note += (cr.note.empty() ? "" : "; ") +
                               JointNote(pool[i == b ? k : b].effect, r, j,
                                         Separation(pool[b].effect, pool[k].effect));
                }
                sel.joint_pairs.push_back({pool[b].effect, pool[k].effect, ambiguous.size()});
                ambiguous.push_back(pool[b].effect + " vs " + pool[k].effect);
                for (size_t i : {b, k}) {
                    terms.push_back(scores[i].term);
                    added_effects.push_back(pool[i].effect);
                    joint.push_back(pool[i].effect);
                }
                MatrixXd xn(x.rows(), x.cols() + 2);
                xn << x, scores[b].column, scores[k].column;
                x = xn;
                pool.erase(pool.begin() + static_cast<long>(std::max(b, k)));
                pool.erase(pool.begin() + static_cast<long>(std::min(b, k)));
                continue;
            }
        }
        if (!twins.empty()) {
            std::vector<size_t> drop = twins;
            drop.push_back(b);
            for (size_t k : twins) {
                const double r = ProjectedCorrelation(x, scores[b].column, scores[k].column);
                for (size_t i : {b, k}) {
                    CandidateResult& cr = last[pool[i].effect];
                    cr.decision = Decision::kAmbiguous;
                    const std::string other = pool[i == b ? k : b].effect;
                    cr.note += (cr.note.empty() ? "" : "; ") + std::string("ambiguous with ") +
                               other + " (projected correlation " + text::Sig(r, 3) +
                               "); to separate: " + Separation(pool[b].effect, pool[k].effect);
                }
                ambiguous.push_back(pool[b].effect + " vs " + pool[k].effect);
            }
            std::sort(drop.rbegin(), drop.rend());
            for (size_t k : drop) pool.erase(pool.begin() + static_cast<long>(k));
            continue;
        }
        last[pool[b].effect].decision = Decision::kAdded;
        terms.push_back(scores[b].term);
        added_effects.push_back(pool[b].effect);
        MatrixXd xn(x.rows(), x.cols() + 1);
        xn << x, scores[b].column;
        x = xn;
        pool.erase(pool.begin() + static_cast<long>(b));
    }
    // Backward re-test: each added term with all the others in the model and the model's own
    // residuals as the noise; the weakest below min_z2 is removed, and so on.
    for (;;) {
        const LsFit f = FitLs(x, c.y, c.segment, c.hac_lag);
        if (!f.ok || terms.size() == o.offset_terms.size()) break;
        size_t weakest = 0;
        double weakest_z2 = INFINITY;
        for (size_t k = o.offset_terms.size(); k < terms.size(); ++k) {
            // A pair added jointly is collinear by construction: each alone has a wide variance
            // with the other in; it passed as a pair and stays as one.
            const std::string& e = added_effects[k - o.offset_terms.size()];
            if (std::find(joint.begin(), joint.end(), e) != joint.end()) continue;
            const auto i = static_cast<Index>(k);
            const double z2 = f.coeffs[i] * f.coeffs[i] / f.covariance(i, i);
            if (z2 < weakest_z2) weakest_z2 = z2, weakest = k;
        }
        if (weakest_z2 > o.min_z2) break;
        const std::string effect = added_effects[weakest - o.offset_terms.size()];
        std::string others;
        for (const std::string& e : added_effects)
            if (e != effect) others += (others.empty() ? "" : ", ") + e;
        CandidateResult& r = last[effect];
        r.decision = Decision::kRejected;
        r.z2 = weakest_z2;
        r.note = "removed on re-test with " + others + " in the model (z2 " +
                 text::Sig(weakest_z2, 3) + ")";
        terms.erase(terms.begin() + static_cast<long>(weakest));
        added_effects.erase(added_effects.begin() +
                            static_cast<long>(weakest - o.offset_terms.size()));
        MatrixXd xn(x.rows(), x.cols() - 1);
        const auto w = static_cast<Index>(weakest);
        xn << x.leftCols(w), x.rightCols(x.cols() - w - 1);
        x = xn;
    }
    for (auto& [effect, r] : last) sel.candidates.push_back(r);
    sel.x = x;
    return sel;
}

}  // namespace gyrocal::analysis::detail
