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

FitResult FitWls(const std::vector<FitPoint>& pts, const std::vector<std::string>& names,
                 double t0_c, const std::string& quantity, double max_cond) {
    if (auto bad = CheckFinite(pts)) return *bad;
    const auto n = static_cast<Index>(pts.size());
    const auto p = static_cast<Index>(names.size());
    if (p < 1 || n < p)
        return Refuse(Refusal::kNotApplicable, std::to_string(p) + " terms need at least " +
                                                   std::to_string(p) + " points, have " +
                                                   std::to_string(n));
    std::vector<model::ResolvedTerm> terms;
    try {
        terms = model::ResolveTerms(names);
    } catch (const model::ModelError& e) {
        return Refuse(Refusal::kNotApplicable, e.what());
    }
    MatrixXd A(n, p);
    VectorXd y(n), sigma(n);
    for (Index i = 0; i < n; ++i) {
        const FitPoint& pt = pts[static_cast<size_t>(i)];
        A.row(i) = model::TermValues(terms, t0_c, pt.inputs).transpose();
        if (!A.row(i).allFinite())
            return Refuse(Refusal::kNonFiniteInput,
                          "point " + std::to_string(pt.id) +
                              ": a term has no value (an input it needs is missing)");
        y[i] = pt.y;
        sigma[i] = pt.sigma_y;
    }
    // The one solver (numeric/least_squares.hpp): rows whitened by 1/sigma, columns scaled to
    // unit norm, so the condition number measures the geometry of the temperatures, not the units
    // of the terms.
    numeric::LeastSquaresOptions lo;
    lo.min_diag_ratio = 0.0;  // the condition number below decides what is ill-posed
    lo.want_condition_number = true;
    const numeric::LeastSquares ls = numeric::SolveLeastSquares(A, y, &sigma, lo);
    if (ls.bad_column >= 0)
        return Refuse(
            Refusal::kIllConditioned,
            "term '" + names[static_cast<size_t>(ls.bad_column)] + "' is zero at every point");
    const double cond = ls.condition_number;
    if (!(cond <= max_cond))
        return Refuse(Refusal::kIllConditioned,
                      "design matrix condition number " + text::Sig(cond, 4) + " exceeds " +
                          text::Sig(max_cond, 4) + ": the points cannot separate the terms");
    if (!ls.ok) return Refuse(Refusal::kIllConditioned, ls.why);

    FitResult out;
    model::Model& m = out.model;
    m.quantity = quantity;
    m.term_names = names;
    m.coeffs = ls.coeffs;
    m.covariance = ls.xtwx_inv;  // (A'WA)^-1, exactly symmetric
    m.t0_c = t0_c;
    SetRange(m, pts);
    m.n_points = static_cast<int32_t>(n);
    m.condition_number = cond;
    m.method = "wls";
    FillFitStats(out, ls.residuals, sigma, static_cast<int>(p));
    out.used_ids = Ids(pts);
    return out;
}

FitResult FitWeightedMean(const std::vector<FitPoint>& pts, const std::string& quantity) {
    if (pts.empty()) return Refuse(Refusal::kNotApplicable, "no points");
    // A constant has no dT, so t0 only labels the model: the first point's temperature.
    const double t0 = pts[0].inputs.temp_c;
    FitResult out = FitWls(pts, {"1"}, std::isfinite(t0) ? t0 : 25.0, quantity);
    if (out.ok()) out.model.method = "mean";
    return out;
}

}  // namespace gyrocal::fit
