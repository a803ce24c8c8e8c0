#include "fit_util.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace gyrocal::fit::detail {

using Eigen::MatrixXd;
using Eigen::VectorXd;

std::string Fmt(double v, int prec) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.*g", prec, v);
    return buf;
}

FitResult Refuse(Refusal r, std::string detail) {
    FitResult out;
    out.refusal = r;
    out.detail = std::move(detail);
    return out;
}

double ConditionNumber(const MatrixXd& m) {
    Eigen::JacobiSVD<MatrixXd> svd(m);
    const VectorXd& sv = svd.singularValues();
    if (sv.size() == 0 || !(sv[sv.size() - 1] > 0.0))
        return std::numeric_limits<double>::infinity();
    return sv[0] / sv[sv.size() - 1];
}

std::optional<FitResult> CheckFinite(const std::vector<FitPoint>& pts) {
    for (const FitPoint& p : pts) {
        if (!std::isfinite(p.inputs.temp_c) || !std::isfinite(p.y) || !std::isfinite(p.sigma_y))
            return Refuse(Refusal::kNonFiniteInput,
                          "point " + std::to_string(p.id) +
                              ": temp_c, value and standard error must be finite");
        if (!(p.sigma_y > 0.0))
            return Refuse(Refusal::kBadStandardError, "point " + std::to_string(p.id) +
                                                          ": standard error " + Fmt(p.sigma_y) +
                                                          " must be > 0");
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
        s += ", chi2/dof " + Fmt(r.chi2_per_dof, 3) + " on " + std::to_string(r.dof) + " dof";
    if (r.scatter_exceeds_errors)
        s += ": scatter exceeds the stated standard errors (model too small or errors understated)";
    return s;
}

namespace {

// Continued fraction of the regularised incomplete beta (modified Lentz), valid for
// x < (a + 1) / (a + b + 2); the caller uses the symmetry otherwise.
double BetaContinuedFraction(double a, double b, double x) {
    constexpr double kTiny = 1e-300;
    double c = 1.0, d = 1.0 - (a + b) * x / (a + 1.0);
    d = 1.0 / (std::abs(d) < kTiny ? kTiny : d);
    double h = d;
    for (int m = 1; m <= 300; ++m) {
        for (int half = 0; half < 2; ++half) {
            const double num = half == 0
                                   ? m * (b - m) * x / ((a + 2 * m - 1) * (a + 2 * m))
                                   : -(a + m) * (a + b + m) * x / ((a + 2 * m) * (a + 2 * m + 1));
            d = 1.0 + num * d;
            d = 1.0 / (std::abs(d) < kTiny ? kTiny : d);
            c = 1.0 + num / c;
            if (std::abs(c) < kTiny) c = kTiny;
            h *= d * c;
            if (half == 1 && std::abs(d * c - 1.0) < 1e-15) return h;
        }
    }
    return h;
}

double RegularisedBeta(double a, double b, double x) {
    if (x <= 0.0) return 0.0;
    if (x >= 1.0) return 1.0;
    const double front = std::exp(std::lgamma(a + b) - std::lgamma(a) - std::lgamma(b) +
                                  a * std::log(x) + b * std::log1p(-x));
    if (x < (a + 1.0) / (a + b + 2.0)) return front * BetaContinuedFraction(a, b, x) / a;
    return 1.0 - front * BetaContinuedFraction(b, a, 1.0 - x) / b;
}

}  // namespace

double FOneUpperQuantile(double upper_tail, int nu) {
    const double n = static_cast<double>(nu);
    auto tail = [&](double x) { return RegularisedBeta(0.5 * n, 0.5, n / (n + x)); };
    double lo = 1e-12, hi = 1e12;  // tail(lo) ~ 1, tail(hi) ~ 0; tail decreases with x
    for (int k = 0; k < 200; ++k) {
        const double mid = std::sqrt(lo * hi);
        (tail(mid) > upper_tail ? lo : hi) = mid;
        if (hi / lo < 1.0 + 1e-12) break;
    }
    return std::sqrt(lo * hi);
}

}  // namespace gyrocal::fit::detail
