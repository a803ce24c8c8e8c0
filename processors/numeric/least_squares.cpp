#include "processors/numeric/least_squares.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

namespace gyrocal::numeric {

using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::VectorXd;

namespace {

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();

LeastSquares Refused(std::string why) {
    LeastSquares r;
    r.why = std::move(why);
    return r;
}

}  // namespace

double ConditionNumber(const MatrixXd& m) {
    const Eigen::JacobiSVD<MatrixXd> svd(m);
    const VectorXd& sv = svd.singularValues();
    if (sv.size() == 0 || !(sv[sv.size() - 1] > 0.0))
        return std::numeric_limits<double>::infinity();
    return sv[0] / sv[sv.size() - 1];
}

LeastSquares SolveLeastSquares(const MatrixXd& x, const VectorXd& y, const VectorXd* sigma,
                               const LeastSquaresOptions& o) {
    const Index n = x.rows(), p = x.cols();
    if (y.size() != n || (sigma && sigma->size() != n))
        throw std::invalid_argument(
            "least squares: " + std::to_string(n) + " design rows, " + std::to_string(y.size()) +
            " values" + (sigma ? ", " + std::to_string(sigma->size()) + " sigmas" : ""));
    if (p == 0 || n < p)
        return Refused(std::to_string(p) + " terms need at least " + std::to_string(p) +
                       " rows, have " + std::to_string(n));
    MatrixXd xw;
    VectorXd yw;
    if (sigma) {
        const VectorXd ws = sigma->cwiseInverse();
        xw = ws.asDiagonal() * x;
        yw = ws.cwiseProduct(y);
    }
    const MatrixXd& a = sigma ? xw : x;
    const VectorXd& b = sigma ? yw : y;
    const VectorXd s = a.colwise().norm();
    for (Index j = 0; j < p; ++j)
        if (!(s[j] > 0.0) || !std::isfinite(s[j])) {
            LeastSquares r =
                Refused("column " + std::to_string(j) + " is zero at every row or not finite");
            r.bad_column = static_cast<int>(j);
            return r;
        }
    const MatrixXd as = a * s.cwiseInverse().asDiagonal();
    LeastSquares r;
    if (o.want_condition_number) r.condition_number = ConditionNumber(as);
    const Eigen::ColPivHouseholderQR<MatrixXd> qr(as);
    r.rank = static_cast<int>(qr.rank());
    if (qr.rank() < p) {
        r.why = "design matrix rank " + std::to_string(qr.rank()) + " < " + std::to_string(p) +
                " terms: the data cannot separate the terms";
        return r;
    }
    const MatrixXd rt = qr.matrixR().topLeftCorner(p, p).triangularView<Eigen::Upper>();
    const double diag_ratio =
        rt.diagonal().cwiseAbs().minCoeff() / rt.diagonal().cwiseAbs().maxCoeff();
    if (!(diag_ratio > o.min_diag_ratio)) {
        r.why = "design matrix nearly rank-deficient (smallest/largest R diagonal " +
                std::to_string(diag_ratio) + "): the data cannot separate the terms";
        return r;
    }
    r.coeffs = qr.solve(b).cwiseQuotient(s);
    const MatrixXd rinv = rt.triangularView<Eigen::Upper>().solve(MatrixXd::Identity(p, p));
    const MatrixXd cu =
        qr.colsPermutation() * (rinv * rinv.transpose()) * qr.colsPermutation().transpose();
    const VectorXd sinv = s.cwiseInverse();
    r.xtwx_inv = sinv.asDiagonal() * cu * sinv.asDiagonal();
    r.xtwx_inv = 0.5 * (r.xtwx_inv + r.xtwx_inv.transpose());
    r.residuals = y - x * r.coeffs;
    r.rss = sigma ? r.residuals.cwiseQuotient(*sigma).squaredNorm() : r.residuals.squaredNorm();
    r.ok = true;
    return r;
}

double ResidualVariance(double rss, Index n, Index p) {
    return n > p ? rss / static_cast<double>(n - p) : kNan;
}

double MeanLeverage(const MatrixXd& x_fit, const MatrixXd& x_other) {
    if (x_other.rows() == 0 || x_fit.rows() <= x_fit.cols()) return kNan;
    const LeastSquares ls = SolveLeastSquares(x_fit, VectorXd::Zero(x_fit.rows()));
    if (!ls.ok) return kNan;
    return (x_other * ls.xtwx_inv).cwiseProduct(x_other).rowwise().sum().mean();
}

MatrixXd ProjectOut(const MatrixXd& base, const MatrixXd& a) {
    if (base.cols() == 0) return a;
    const VectorXd s = base.colwise().norm().cwiseMax(1e-300);
    const MatrixXd bs = base * s.cwiseInverse().asDiagonal();
    const Eigen::ColPivHouseholderQR<MatrixXd> qr(bs);
    return a - bs * qr.solve(a);
}

MatrixXd OrthonormalBasis(const MatrixXd& x) {
    if (x.cols() == 0) return MatrixXd(x.rows(), 0);
    const Eigen::ColPivHouseholderQR<MatrixXd> qr(x);
    return qr.householderQ() * MatrixXd::Identity(x.rows(), qr.rank());
}

}  // namespace gyrocal::numeric
