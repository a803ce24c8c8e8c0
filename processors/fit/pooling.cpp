#include "processors/fit/pooling.hpp"

#include <algorithm>

#include "lcmtypes/text/number.hpp"
#include "processors/numeric/distributions.hpp"

namespace gyrocal::fit {

namespace {

std::string Describe(const UnitEvidence& u, double c_rest, int dof_rest, double p) {
    return text::Printf(
        "overdispersion %.3g on %d dof disagrees with the other units' %.3g on %d dof "
        "(F test, two-sided p = %.2g): not pooled",
        u.chi2 / u.dof, u.dof, c_rest, dof_rest, p);
}

}  // namespace

Pool Pool::Decide(const std::vector<UnitEvidence>& units, double alpha) {
    Pool pool;
    for (const UnitEvidence& u : units)
        if (u.dof > 0 && u.chi2 >= 0.0) pool.in_[u.id] = u;
    while (pool.in_.size() >= 2) {
        double total_chi2 = 0;
        int total_dof = 0;
        for (const auto& [id, u] : pool.in_) {
            total_chi2 += u.chi2;
            total_dof += u.dof;
        }
        std::string worst;
        double worst_p = 2.0, worst_c = 0;
        int worst_dof = 0;
        for (const auto& [id, u] : pool.in_) {
            const int dof_rest = total_dof - u.dof;
            const double c_rest = (total_chi2 - u.chi2) / dof_rest;
            if (!(c_rest > 0.0)) continue;
            const double f = (u.chi2 / u.dof) / c_rest;
            const double upper = numeric::FUpperTail(f, u.dof, dof_rest);
            const double p = std::min(1.0, 2.0 * std::min(upper, 1.0 - upper));
            if (p < worst_p) {
                worst_p = p;
                worst = id;
                worst_c = c_rest;
                worst_dof = dof_rest;
            }
        }
        if (worst.empty() || worst_p >= alpha / static_cast<double>(pool.in_.size())) break;
        pool.left_out_[worst] = Describe(pool.in_[worst], worst_c, worst_dof, worst_p);
        pool.in_.erase(worst);
    }
    return pool;
}

std::string Disagreement(const UnitEvidence& u, const PooledEvidence& others, double alpha) {
    if (u.dof <= 0 || others.dof <= 0 || !(others.chi2 > 0.0)) return "";
    const double c_rest = others.chi2 / others.dof;
    const double upper = numeric::FUpperTail((u.chi2 / u.dof) / c_rest, u.dof, others.dof);
    const double p = std::min(1.0, 2.0 * std::min(upper, 1.0 - upper));
    return p < alpha ? Describe(u, c_rest, others.dof, p) : "";
}

PooledEvidence Pool::For(const std::string& id) const {
    PooledEvidence e;
    if (left_out_.count(id)) return e;
    for (const auto& [other, u] : in_) {
        if (other == id) continue;
        e.chi2 += u.chi2;
        e.dof += u.dof;
    }
    return e;
}

}  // namespace gyrocal::fit
