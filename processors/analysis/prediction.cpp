// The published set is for prediction (analyze.hpp, CarryForPrediction): a term the verdict did
// not name on evidence, carried when it lowers the held-out error.
#include <algorithm>
#include <cmath>

#include "lcmtypes/text/number.hpp"
#include "processors/analysis/analyze.hpp"
#include "processors/analysis/candidates.hpp"
#include "processors/analysis/heldout.hpp"
#include "processors/analysis/regress.hpp"
#include "processors/analysis/residual.hpp"
#include "processors/analysis/steps.hpp"

namespace gyrocal::analysis {

using Eigen::Index;

std::string CarryForPrediction(const BinnedRun& binned, const AnalysisOptions& o,
                               const std::string& effect, const std::string& term,
                               SensorResult& r) {
    if (!r.extended_offset) return "";
    std::vector<std::string> terms = r.extended_offset->term_names;
    if (std::find(terms.begin(), terms.end(), term) != terms.end()) return "";
    const auto c = std::find_if(r.candidates.begin(), r.candidates.end(),
                                [&](const CandidateResult& x) { return x.effect == effect; });
    if (c == r.candidates.end() || c->decision == Decision::kNotTested) return "";
    // A residual that follows time (a drift, a slow transient) is not a curve in temperature: on
    // a profile where the two move together a temperature term would lower the held-out error
    // as a proxy for time and carry it into runs of another profile (aging on a monotonic
    // profile: seen in OutsideEffectEndToEnd, dT^3 carried, 2026-11-29).
    for (const FeatureResult& f : r.features)
        if (f.explains_heldout && (f.channel == "time" || f.channel == "time since power-on")) {
            const std::string note = term + " not carried for prediction: the residual follows " +
                                     f.feature + " [" + f.channel +
                                     "], which a temperature term could only stand in for";
            r.notes.push_back(note);
            return note;
        }
    const double t0 = r.extended_offset->t0_c;
    const detail::Split split = detail::MakeSplit(binned.bins(), o);
    const detail::Context train = detail::MakeContext(binned, split.train, t0, o);
    std::vector<std::string> with = terms;
    with.push_back(term);
    const Eigen::MatrixXd none(static_cast<Index>(binned.size()), 0);
    const Eigen::VectorXd r_wo =
        detail::HeldResidual(binned, train, split, train.AllDesign(terms), none);
    const Eigen::VectorXd r_w =
        detail::HeldResidual(binned, train, split, train.AllDesign(with), none);
    if (r_wo.size() == 0 || r_w.size() != r_wo.size()) return "";
    const detail::Gain g = detail::HeldOutGain(r_wo, r_w, split.held_block, train.hac_lag);
    const std::string figures = "held-out squared error " +
                                text::Sig(r_wo.squaredNorm() / r_wo.size(), 3) + " -> " +
                                text::Sig(r_w.squaredNorm() / r_w.size(), 3) + " V^2";
    if (!(g.mean_v2 > 0.0)) return term + " not carried for prediction (" + figures + ")";
    const detail::Context all = detail::MakeContext(binned, detail::AllRows(binned.size()), t0, o);
    const LsFit fe = FitLs(all.Design(with), all.y, all.segment, all.hac_lag);
    const LsFit ft = FitLs(train.Design(with), train.y, train.segment, train.hac_lag);
    if (!fe.ok || !ft.ok) return "";
    r.extended_offset = detail::FitModel(with, t0, binned, all.rows, fe);
    r.residual_all_extended_rms_v = std::sqrt(fe.rss / static_cast<double>(binned.size()));
    for (AddedEffect& a : r.added)
        for (size_t k = 0; k < with.size(); ++k)
            if (a.term == with[k]) {
                a.coefficient = fe.coeffs[static_cast<Index>(k)];
                a.stderr_ = std::sqrt(fe.covariance(static_cast<Index>(k), static_cast<Index>(k)));
            }
    r.holdout_after_offset = detail::FitModel(with, t0, binned, train.rows, ft);
    r.error_after =
        detail::ErrorsOn(binned, detail::Residuals(binned, *r.holdout_after_offset, split.held),
                         split.held, split.held_block, r.declared_sensitivity);
    const std::string note = term +
                             " carried for prediction in the published set, not named as an "
                             "effect (" +
                             effect + " z^2 " + text::Sig(c->z2, 3) + "; " + figures + ")";
    r.notes.push_back(note);
    return note;
}

}  // namespace gyrocal::analysis
