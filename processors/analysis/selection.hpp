#pragma once
// Internal to gyrocal_analysis: the choice of the offset terms (analyze.hpp, step 4): forward
// selection with the full-model noise, the collinearity check (ambiguous pairs are dropped, with
// the measurement that would separate them), and the backward re-test of every added term.
#include <Eigen/Dense>
#include <string>
#include <vector>

#include "processors/analysis/analyze.hpp"
#include "processors/analysis/bins.hpp"
#include "processors/analysis/candidates.hpp"
#include "processors/analysis/score.hpp"

namespace gyrocal::analysis::detail {

struct Selection {
    std::vector<std::string> terms;          // declared terms + the added ones
    std::vector<std::string> added_effects;  // effect of each added term, in order
    std::vector<std::string> ambiguous;      // "a vs b"
    // Collinear pairs added whole (a, b, index of their "a vs b" in `ambiguous`): the caller says
    // in that entry what became of them (both kept, one not attributed, not confirmed).
    struct JointPair {
        std::string a, b;
        size_t ambiguous_index = 0;
    };
    std::vector<JointPair> joint_pairs;
    std::vector<CandidateResult> candidates;  // latest statistics of each tested candidate
    Eigen::MatrixXd x;                        // design of `terms` on the bins
};

// pool: the testable candidates; floor: the noise floor of the data (for (c)).
Selection SelectOffsetTerms(const Context& c, std::vector<Candidate> pool, const Floor& floor,
                            const AnalysisOptions& o);

}  // namespace gyrocal::analysis::detail
