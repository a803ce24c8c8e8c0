#pragma once
// Helpers shared by the fit's translation units (not part of the public interface).
#include <optional>
#include <string>
#include <vector>

#include "fit.hpp"

namespace gyrocal::fit::detail {

std::string Fmt(double v, int prec = 4);
FitResult Refuse(Refusal r, std::string detail);
// Condition number of a matrix with full column rank: ratio of extreme singular values.
double ConditionNumber(const Eigen::MatrixXd& m);
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
// 0 < upper_tail < 1. F(1, nu) = t_nu^2, and P(t_nu^2 > x) = I_{nu/(nu+x)}(nu/2, 1/2) (regularised
// incomplete beta, continued fraction), solved for x by bisection on log x.
double FOneUpperQuantile(double upper_tail, int nu);

}  // namespace gyrocal::fit::detail
