#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "fit_util.hpp"

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
    // Whiten rows, scale columns to unit norm: the condition number then measures the geometry of
    // the temperatures, not the units of the terms.
    const VectorXd ws = sigma.cwiseInverse();
    const MatrixXd Aw = ws.asDiagonal() * A;
    const VectorXd yw = ws.cwiseProduct(y);
    const VectorXd s = Aw.colwise().norm();
    for (Index j = 0; j < p; ++j)
        if (!(s[j] > 0.0))
            return Refuse(Refusal::kIllConditioned,
                          "term '" + names[static_cast<size_t>(j)] + "' is zero at every point");
    const MatrixXd As = Aw * s.cwiseInverse().asDiagonal();
    const double cond = ConditionNumber(As);
    if (!(cond <= max_cond))
        return Refuse(Refusal::kIllConditioned, "design matrix condition number " + Fmt(cond) +
                                                    " exceeds " + Fmt(max_cond) +
                                                    ": the points cannot separate the terms");
    const Eigen::ColPivHouseholderQR<MatrixXd> qr(As);
    if (qr.rank() < p)
        return Refuse(Refusal::kIllConditioned, "design matrix rank " + std::to_string(qr.rank()) +
                                                    " < " + std::to_string(p) + " terms");
    const VectorXd u = qr.solve(yw);
    // Covariance of u is (As'As)^-1 = P R^-1 R^-T P' (As P = Q R); R^-1 from a triangular solve.
    const MatrixXd R = qr.matrixR().topLeftCorner(p, p).triangularView<Eigen::Upper>();
    const MatrixXd Rinv = R.triangularView<Eigen::Upper>().solve(MatrixXd::Identity(p, p));
    const MatrixXd cov_u =
        qr.colsPermutation() * (Rinv * Rinv.transpose()) * qr.colsPermutation().transpose();
    const VectorXd sinv = s.cwiseInverse();

    FitResult out;
    model::Model& m = out.model;
    m.quantity = quantity;
    m.term_names = names;
    m.coeffs = u.cwiseProduct(sinv);
    m.covariance = sinv.asDiagonal() * cov_u * sinv.asDiagonal();
    m.covariance = 0.5 * (m.covariance + m.covariance.transpose());  // exact symmetry for consumers
    m.t0_c = t0_c;
    SetRange(m, pts);
    m.n_points = static_cast<int32_t>(n);
    m.condition_number = cond;
    m.method = "wls";
    FillFitStats(out, y - A * m.coeffs, sigma, static_cast<int>(p));
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
