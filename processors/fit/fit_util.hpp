#pragma once
// Helpers shared by the fit's translation units (not part of the public interface).
#include <optional>
#include <string>
#include <vector>

#include "processors/fit/fit.hpp"

namespace gyrocal::fit::detail {

FitResult Refuse(Refusal r, std::string detail);
// A refusal when a point has a non-finite value or a non-positive standard error.
std::optional<FitResult> CheckFinite(const std::vector<FitPoint>& pts);
// residuals, chi2, dof, chi2/dof, the 3-sigma scatter flag and the weighted residual RMS.
void FillFitStats(FitResult& out, const Eigen::VectorXd& residuals, const Eigen::VectorXd& sigma,
                  int p);
std::vector<int64_t> Ids(const std::vector<FitPoint>& pts);
std::vector<double> Temps(const std::vector<FitPoint>& pts);
void SetRange(model::Model& m, const std::vector<FitPoint>& pts);
// chi2/dof and, when it is out of its band, the warning a person must see.
std::string FitNotes(const FitResult& r);
// Upper quantile of the F(1, nu) distribution: the x with P(F > x) = upper_tail; nu >= 1,
// 0 < upper_tail < 1 (numeric/distributions.hpp).
double FOneUpperQuantile(double upper_tail, int nu);

// The overdispersion c (fit.hpp) from a reference model's chi2 and dof plus what the caller
// pooled; c is NaN without dof.
struct Overdispersion {
    double c = model::kUnknown;
    int dof = 0;
};
Overdispersion EstimateOverdispersion(double reference_chi2, int reference_dof,
                                      const FitOptions& o);
// Fills the overdispersion fields of `out` and scales its covariance by max(1, c).
void ApplyOverdispersion(FitResult& out, double reference_chi2, int reference_dof,
                         const FitOptions& o);
std::string OverdispersionNotes(const FitResult& r);

}  // namespace gyrocal::fit::detail
