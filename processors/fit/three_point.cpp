#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "lcmtypes/text/number.hpp"
#include "processors/fit/fit_util.hpp"
#include "processors/numeric/least_squares.hpp"

namespace gyrocal::fit {

using namespace detail;
using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::VectorXd;

FitResult SeedThreePoint(const std::vector<FitPoint>& pts, const std::string& quantity) {
    if (pts.size() != 3)
        return Refuse(Refusal::kNotApplicable, "the 3-point method needs exactly 3 points, have " +
                                                   std::to_string(pts.size()));
    if (auto bad = CheckFinite(pts)) return *bad;
    const double T0 = pts[0].inputs.temp_c, V0 = pts[0].y;
    const double d1 = pts[1].inputs.temp_c - T0, d2 = pts[2].inputs.temp_c - T0;
    // The full square system [1 d d^2] p = V, column-scaled, tells whether the temperatures are
    // distinct enough to solve at all; the 2x2 below is the seed's own form of the same system.
    MatrixXd A3(3, 3);
    A3 << 1, 0, 0, 1, d1, d1 * d1, 1, d2, d2 * d2;
    const VectorXd scale = A3.colwise().norm();
    const double cond = numeric::ConditionNumber(A3 * scale.cwiseInverse().asDiagonal());
    if (!(cond < kMaxThreePointConditionNumber))
        return Refuse(Refusal::kIllConditioned,
                      "3-point temperatures " + text::Sig(T0, 4) + ", " + text::Sig(T0 + d1, 4) +
                          ", " + text::Sig(T0 + d2, 4) +
                          " degC do not determine a quadratic (condition number " +
                          text::Sig(cond, 4) + ")");
    Eigen::Matrix2d A2;
    A2 << d1, d1 * d1, d2, d2 * d2;
    const Eigen::Vector2d rhs(pts[1].y - V0, pts[2].y - V0);
    const Eigen::Vector2d ab = A2.colPivHouseholderQr().solve(rhs);

    FitResult out;
    model::Model& m = out.model;
    m.quantity = quantity;
    m.term_names = model::PolynomialTerms(2);
    m.coeffs = Eigen::Vector3d(V0, ab[0], ab[1]);
    // p = A3^-1 V is linear in V, so cov(p) = X X' with X = A3^-1 diag(sigma) (solved, not
    // inverted).
    const Eigen::Vector3d sigma(pts[0].sigma_y, pts[1].sigma_y, pts[2].sigma_y);
    const MatrixXd X = A3.colPivHouseholderQr().solve(MatrixXd(sigma.asDiagonal()));
    m.covariance = X * X.transpose();
    m.t0_c = T0;
    SetRange(m, pts);
    m.n_points = 3;
    m.condition_number = cond;
    m.method = "3point";
    FillFitStats(out, VectorXd::Zero(3), sigma, 3);
    out.used_ids = Ids(pts);
    out.detail = "seed 3-point solution (exact, no degrees of freedom left to check it)";
    return out;
}

}  // namespace gyrocal::fit
