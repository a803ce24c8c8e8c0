#include "selection.hpp"

#include <algorithm>
#include <cmath>
#include <map>

#include "regress.hpp"

namespace gyrocal::analysis::detail {

using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::VectorXd;

Selection SelectOffsetTerms(const Context& c, std::vector<Candidate> pool, const Floor& floor,
                            const AnalysisOptions& o) {
    Selection sel;
    std::vector<std::string>& terms = sel.terms;
    std::vector<std::string>& added_effects = sel.added_effects;
    std::vector<std::string>& ambiguous = sel.ambiguous;
    terms = o.offset_terms;
    std::map<std::string, CandidateResult> last;  // latest statistics of each pool candidate
    MatrixXd x = Design(terms, c.t0, *c.bins, c.first_utime);
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
        for (size_t k = 0; k < pool.size(); ++k) {
            if (noise)
                scores[k] = Score(c, x, base_cv, pool[k], o, noise, static_cast<int>(xfull.cols()));
            const StepScore& s = scores[k];
            CandidateResult& r = last[pool[k].effect];
            r = {pool[k].effect, s.term, Decision::kRejected, s.z2, s.cv_gain,
                 step,           "",     s.effect_rms_v};
            if (!s.ok) r.note = "could not be fitted with the current model";
            const bool big_enough = !std::isfinite(floor.offset_rms_v) ||
                                    s.effect_rms_v > o.min_effect_floor_ratio * floor.offset_rms_v;
            if (s.ok && !big_enough)
                r.note = "effect RMS " + Fmt(s.effect_rms_v) + " V is below " +
                         Fmt(o.min_effect_floor_ratio) + "x the noise floor " +
                         Fmt(floor.offset_rms_v) + " V";
            const bool pass = s.ok && s.z2 > o.min_z2 && s.cv_gain > o.min_cv_gain && big_enough;
            // The best explains the most (smallest residual sum of squares), not the largest
            // z^2: a candidate correlated with a stronger missing effect borrows its signal.
            if (pass && (best < 0 || s.rss < scores[static_cast<size_t>(best)].rss))
                best = static_cast<int>(k);
        }
        if (best < 0) break;
        const auto b = static_cast<size_t>(best);
        std::vector<size_t> twins;
        for (size_t k = 0; k < pool.size(); ++k) {
            if (k == b || scores[k].column.size() == 0) continue;
            const double r = ProjectedCorrelation(x, scores[b].column, scores[k].column);
            if (std::isfinite(r) && std::fabs(r) > o.max_collinearity) twins.push_back(k);
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
        pool.erase(pool.begin() + best);
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
