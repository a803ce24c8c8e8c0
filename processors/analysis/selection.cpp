#include "selection.hpp"

#include <algorithm>
#include <cmath>
#include <map>

#include "regress.hpp"

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

}  // namespace

Selection SelectOffsetTerms(const Context& c, std::vector<Candidate> pool, const Floor& floor,
                            const AnalysisOptions& o) {
    Selection sel;
    std::vector<std::string>& terms = sel.terms;
    std::vector<std::string>& added_effects = sel.added_effects;
    std::vector<std::string>& ambiguous = sel.ambiguous;
    terms = o.offset_terms;
    std::map<std::string, CandidateResult> last;  // latest statistics of each pool candidate
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
                r.note = "effect RMS " + Fmt(s.effect_rms_v) + " V is below " +
                         Fmt(o.min_effect_floor_ratio) + "x the noise floor " +
                         Fmt(floor.offset_rms_v) + " V";
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
                              Fmt(r, 3) + "); with both in the model " + pool[b].effect +
                              " keeps z2 " + Fmt(e.z2_best) + ", " + pool[k].effect + " " +
                              Fmt(e.z2_other);
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
                               other + " (projected correlation " + Fmt(r, 3) +
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
        r.note = "removed on re-test with " + others + " in the model (z2 " + Fmt(weakest_z2) + ")";
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
