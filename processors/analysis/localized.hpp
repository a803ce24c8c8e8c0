#pragma once
// Internal to gyrocal_analysis: the check of an effect confined to the start of a power cycle -
// the warm-up (analyze.hpp, step 4) - by data it was not fitted on.
//
// Blocked cross-validation asks a block to predict an effect it does not contain: a transient of a
// few hundred seconds lives in the first block, and a fit without that block cannot see it, so a
// real warm-up (z^2 in the tens of thousands) failed it. Here the support of the transient - the
// first 3 x the largest searched time constant after every power-on - is cut into interleaved
// blocks of early_block_s: the odd ones are held out, the even ones and everything after the
// support are the training data. The warm-up's time constant is chosen on the training data (by
// residual sum of squares), the model with and without it, fitted there, predicts the held-out
// blocks, and the statistic is log(|r0|^2 / |r1|^2) on them: the transient must predict pieces of
// itself it did not see. The blocks are short and unguarded, so slow noise correlated across them
// would pass for a prediction: the statistic is therefore compared with the same search and
// prediction on surrogates of the run's own noise (evidence.hpp), and the warm-up passes when at
// most warmup_fpr of them reach it (p <= warmup_fpr: the stated false-positive rate), together
// with (a) z^2 above min_z2 and (c) its size above the floor, both on all bins.
// The drift rule: a warm-up whose time constant is the grid's largest has not shown its shape (a
// transient slower than the grid, or a drift in time over a profile that only warms or only
// cools, would end there). It is then weighed against a linear drift in time on the same split
// (each fitted on the training data, predicting the held-out blocks), as the named terms are
// weighed against the time shapes elsewhere (displace.cpp): the warm-up passes when it predicts
// the held-out blocks better than the drift and still lowers their error beyond its noise with
// the drift in the model (gate_min_z); when the drift predicts them at least as well, the
// warm-up is not attributed (said as a drift); otherwise the two are ambiguous. Never named a
// warm-up unless its shape shows.
// The step rule: a one-time shift (an offset that changes once, at an event, and stays) makes a
// "transient" of the stretch before it. Every warm-up that passes is weighed the same way
// against a step at a time searched over the run (chosen on the training data): not attributed
// when the step predicts the held-out blocks at least as well, ambiguous when the warm-up
// predicts better but adds nothing beyond its noise with the step in.
#include <optional>
#include <string>

#include "processors/analysis/candidates.hpp"
#include "processors/analysis/evidence.hpp"

namespace gyrocal::analysis::detail {

struct LocalizedCheck {
    bool tested = false, passes = false;
    std::string term;            // the time constant chosen on the training data
    bool grid_edge = false;      // at an end of its grid
    double p = kNan;             // share of surrogates whose statistic reaches the run's
    double drop = kNan;          // [1] fraction of the held-out blocks' squared residual removed
    double z2 = kNan;            // (a) on all bins
    double effect_rms_v = kNan;  // (c) on all bins
    double support_s = kNan;     // [s] after each power-on
    int n_held = 0;
    // The drift rule (tau at the grid's largest; NaN otherwise): the share of the held-out blocks'
    // squared residual a linear drift in time removes, and the fate: kAdded (passes stands),
    // kRejected (the drift predicts at least as well), kAmbiguous (the warm-up predicts better
    // only).
    double drift_drop = kNan;
    std::optional<Decision> drift_rule;
    // The step rule (every warm-up that passes): the same for a one-time shift at a time searched
    // over the run (the step feature), with the time it chose.
    double step_drop = kNan, step_s = kNan;
    std::optional<Decision> step_rule;
    std::string note;  // what was found, or why it could not be tested
};

// all: every bin (with any nuisance columns); base_terms: the model the warm-up is added to.
LocalizedCheck CheckWarmup(const BinnedRun& binned, const Context& all,
                           const std::vector<std::string>& base_terms, const Candidate& warmup,
                           const Surrogates& s, const AnalysisOptions& o);

}  // namespace gyrocal::analysis::detail
