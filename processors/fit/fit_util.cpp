#include "processors/fit/fit_util.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "lcmtypes/text/number.hpp"
#include "processors/numeric/distributions.hpp"

namespace gyrocal::fit::detail {

using Eigen::MatrixXd;
using Eigen::VectorXd;

FitResult Refuse(Refusal r, std::string detail) {
    FitResult out;
    out.refusal = r;
    out.detail = std::move(detail);
    return out;
}

std::optional<FitResult> CheckFinite(const std::vector<FitPoint>& pts) {
    for (const FitPoint& p : pts) {
        if (!std::isfinite(p.inputs.temp_c) || !std::isfinite(p.y) || !std::isfinite(p.sigma_y))
            return Refuse(Refusal::kNonFiniteInput,
                          "point " + std::to_string(p.id) +
                              ": temp_c, value and standard error must be finite");
        if (!(p.sigma_y > 0.0))
            return Refuse(Refusal::kBadStandardError, "point " + std::to_string(p.id) +
                                                          ": standard error " +
                                                          text::Sig(p.sigma_y, 4) + " must be > 0");
    }
    return std::nullopt;
}

double WeightedRms(const VectorXd& r, const VectorXd& sigma) {
    const VectorXd w = sigma.cwiseInverse().cwiseAbs2();
    return std::sqrt((w.array() * r.array().square()).sum() / w.sum());
}

void FillFitStats(FitResult& out, const VectorXd& residuals, const VectorXd& sigma, int p) {
    out.residuals = residuals;
    out.chi2 = residuals.cwiseQuotient(sigma).squaredNorm();
    out.dof = static_cast<int>(residuals.size()) - p;
    if (out.dof > 0) {
        out.chi2_per_dof = out.chi2 / out.dof;
        out.scatter_exceeds_errors = out.chi2_per_dof > 1.0 + 3.0 * std::sqrt(2.0 / out.dof);
    }
    out.model.residual_rms = WeightedRms(residuals, sigma);
}

std::vector<int64_t> Ids(const std::vector<FitPoint>& pts) {
    std::vector<int64_t> ids;
    for (const FitPoint& p : pts) ids.push_back(p.id);
    return ids;
}

std::vector<double> Temps(const std::vector<FitPoint>& pts) {
    std::vector<double> t;
    for (const FitPoint& p : pts) t.push_back(p.inputs.temp_c);
    return t;
}

void SetRange(model::Model& m, const std::vector<FitPoint>& pts) {
    const std::vector<double> t = Temps(pts);
    m.temp_min_c = *std::min_element(t.begin(), t.end());
    m.temp_max_c = *std::max_element(t.begin(), t.end());
}

std::string FitNotes(const FitResult& r) {
    std::string s;
    if (r.dof > 0)
        s += ", chi2/dof " + text::Sig(r.chi2_per_dof, 3) + " on " + std::to_string(r.dof) + " dof";
    if (r.scatter_exceeds_errors)
        s += ": scatter exceeds the stated standard errors (model too small or errors understated)";
    return s;
}

Overdispersion EstimateOverdispersion(double reference_chi2, int reference_dof,
                                      const FitOptions& o) {
    const int own_dof = std::max(0, reference_dof);
    Overdispersion od;
    od.dof = own_dof + o.pooled_dof;
    if (od.dof > 0) od.c = ((own_dof > 0 ? reference_chi2 : 0.0) + o.pooled_chi2) / od.dof;
    return od;
}

void ApplyOverdispersion(FitResult& out, double reference_chi2, int reference_dof,
                         const FitOptions& o) {
    const Overdispersion od = EstimateOverdispersion(reference_chi2, reference_dof, o);
    out.reference_chi2 = reference_dof > 0 ? reference_chi2 : 0.0;
    out.reference_dof = std::max(0, reference_dof);
    out.overdispersion = od.c;
    out.overdispersion_dof = od.dof;
    out.covariance_scale = std::isfinite(od.c) ? std::max(1.0, od.c) : 1.0;
    out.model.covariance *= out.covariance_scale;
}

std::string OverdispersionNotes(const FitResult& r) {
    if (!std::isfinite(r.overdispersion))
        return "; overdispersion not estimated (no dof): covariance from the stated errors";
    return "; overdispersion c " + text::Sig(r.overdispersion, 3) + " on " +
           std::to_string(r.overdispersion_dof) + " dof, covariance x" +
           text::Sig(r.covariance_scale, 3);
}

double FOneUpperQuantile(double upper_tail, int nu) {
    return numeric::FUpperQuantile(upper_tail, 1.0, static_cast<double>(nu));
}

}  // namespace gyrocal::fit::detail
