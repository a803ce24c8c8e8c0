#pragma once
// Which units of a run may share their overdispersion evidence (fit.hpp: pooled_chi2/_dof).
//
// Pooling assumes the units' stated errors are understated by a COMMON factor c (same window,
// chamber and sensor type). A unit whose own c_u = chi2_u / dof_u disagrees with the others would
// drag everyone's covariance with it (one bad unit, 30 sigma off at one plateau, inflates the
// others' about 100x). The test: under a common c, c_u / c_rest ~ F(dof_u, dof_rest), c_rest
// pooled over the other units of the pool. The unit with the smallest two-sided p-value is left
// out when p < alpha / m (Bonferroni over the m units in the pool, alpha = 0.01), and the test is
// repeated on the rest until every remaining unit agrees or fewer than two remain. A unit left
// out gives no evidence to the others; a unit without dof (e.g. three points) is not tested and
// receives the pool's evidence. The fitter decides the pool a unit receives among the OTHER units
// (so that the unit's own bad point, the thing its outlier test must find, cannot deny it the
// others' evidence), and after its fit checks its own evidence against that pool (Disagreement):
// a unit that disagrees is fitted on its own evidence.
#include <map>
#include <string>
#include <vector>

namespace gyrocal::fit {

struct UnitEvidence {
    std::string id;
    double chi2 = 0.0;  // reference model's chi2 (after the unit's own outlier exclusions)
    int dof = 0;
};

struct PooledEvidence {
    double chi2 = 0.0;
    int dof = 0;
};

// "" when unit `u`'s own evidence agrees with the pooled evidence of the others (two-sided F test
// at alpha), else why not (for the fit's notes). No dof on either side: agrees.
std::string Disagreement(const UnitEvidence& u, const PooledEvidence& others, double alpha);

class Pool {
public:
    // The decision over every unit with evidence; alpha is the family-wise false alarm rate.
    static Pool Decide(const std::vector<UnitEvidence>& units, double alpha = 0.01);
    // What unit `id` may pool: the agreeing units other than itself (nothing when it is left out).
    PooledEvidence For(const std::string& id) const;
    // Units left out, with why (for the fit's notes).
    const std::map<std::string, std::string>& left_out() const { return left_out_; }
    int agreeing() const { return static_cast<int>(in_.size()); }

private:
    std::map<std::string, UnitEvidence> in_;
    std::map<std::string, std::string> left_out_;
};

}  // namespace gyrocal::fit
