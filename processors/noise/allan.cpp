#include "processors/noise/allan.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "processors/numeric/distributions.hpp"
#include "processors/numeric/least_squares.hpp"

namespace gyrocal::noise {

namespace {

constexpr double kLn2 = 0.69314718055994530942;

// Equivalent degrees of freedom of one segment of n phase points at m (see header).
double SegmentEdf(double n, double m) {
    if (n < 2 * m + 1) return 0.0;
    const double white =
        (3.0 * (n - 1) / (2.0 * m) - 2.0 * (n - 2) / n) * 4 * m * m / (4 * m * m + 5);
    const double flicker =
        m < 2 ? 2.0 * (n - 2) * (n - 2) / (2.3 * n - 4.9) : 5.0 * n * n / (4.0 * m * (n + 3.0 * m));
    return std::max(1.0, std::min(white, flicker));
}

struct TermFit {
    Eigen::Vector3d theta = Eigen::Vector3d::Zero();  // N^2, B^2, K^2
    Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
    std::vector<bool> active = {true, true, true};
    bool ok = false;
};

// The one solver, with no refusal on conditioning: the tau points are what the run gave.
constexpr numeric::LeastSquaresOptions kTermSolve{0.0, false};

// Weighted least squares of AVAR = N^2/tau + B^2 + K^2 tau/3 with negative terms dropped.
TermFit SolveTerms(const std::vector<AllanPoint>& pts, double min_rrw_tau_s) {
    TermFit f;
    if (pts.empty() || pts.back().tau_s < min_rrw_tau_s) f.active[2] = false;
    const auto n = static_cast<Eigen::Index>(pts.size());
    for (int pass = 0; pass < 3; ++pass) {  // at most one term dropped per pass
        std::vector<int> cols;
        for (int j = 0; j < 3; ++j)
            if (f.active[j]) cols.push_back(j);
        if (cols.empty() || n < static_cast<Eigen::Index>(cols.size())) return f;
        Eigen::VectorXd model(n);
        for (Eigen::Index i = 0; i < n; ++i) model[i] = pts[i].adev * pts[i].adev;
        numeric::LeastSquares ls;
        Eigen::MatrixXd a(n, static_cast<Eigen::Index>(cols.size()));
        for (int iter = 0; iter < 4; ++iter) {  // weights from the model, refreshed
            Eigen::VectorXd y(n);
            for (Eigen::Index i = 0; i < n; ++i) {
                const double tau = pts[i].tau_s;
                const double w =
                    std::sqrt(std::max(pts[i].edf, 1.0) / 2.0) / std::max(model[i], 1e-300);
                const double row[3] = {1.0 / tau, 1.0, tau / 3.0};
                for (size_t c = 0; c < cols.size(); ++c)
                    a(i, static_cast<Eigen::Index>(c)) = w * row[cols[c]];
                y[i] = w * pts[i].adev * pts[i].adev;
            }
            // Rows already whitened by w: ordinary least squares on them is the weighted fit.
            ls = numeric::SolveLeastSquares(a, y, nullptr, kTermSolve);
            if (!ls.ok) return f;
            for (Eigen::Index i = 0; i < n; ++i) {
                const double tau = pts[i].tau_s;
                const double row[3] = {1.0 / tau, 1.0, tau / 3.0};
                double v = 0;
                for (size_t c = 0; c < cols.size(); ++c)
                    v += row[cols[c]] * ls.coeffs[static_cast<Eigen::Index>(c)];
                model[i] = std::max(v, 1e-3 * pts[i].adev * pts[i].adev);
            }
        }
        int most_negative = -1;
        double most = 0.0;
        for (size_t c = 0; c < cols.size(); ++c) {
            const double v = ls.coeffs[static_cast<Eigen::Index>(c)];
            if (v < most) most = v, most_negative = cols[c];
        }
        if (most_negative >= 0) {
            f.active[static_cast<size_t>(most_negative)] = false;
            continue;
        }
        const Eigen::MatrixXd& cov = ls.xtwx_inv;  // (a'a)^-1 of the whitened rows
        f.theta.setZero();
        for (size_t c = 0; c < cols.size(); ++c) {
            f.theta[cols[c]] = ls.coeffs[static_cast<Eigen::Index>(c)];
            for (size_t d = 0; d < cols.size(); ++d)
                f.cov(cols[c], cols[d]) =
                    cov(static_cast<Eigen::Index>(c), static_cast<Eigen::Index>(d));
        }
        f.ok = true;
        return f;
    }
    return f;
}

std::vector<AllanPoint> FromTau(const std::vector<AllanPoint>& all, double min_tau_s) {
    std::vector<AllanPoint> out;
    for (const AllanPoint& p : all)
        if (p.tau_s >= min_tau_s && p.adev > 0 && p.edf >= 1.0) out.push_back(p);
    return out;
}

}  // namespace

std::vector<int64_t> TauGrid(int64_t max_m) {
    std::vector<int64_t> grid;
    for (int k = 0;; ++k) {
        const auto m = static_cast<int64_t>(std::llround(std::pow(2.0, 0.5 * k)));
        if (m > max_m) break;
        if (grid.empty() || m > grid.back()) grid.push_back(m);
    }
    return grid;
}

SegmentSums SumSegment(const std::vector<double>& y, double tau0_s,
                       const std::vector<int64_t>& grid, int64_t bins_per_m) {
    SegmentSums s;
    const auto m_bins = static_cast<int64_t>(y.size());
    s.bins = m_bins;
    s.length_s = static_cast<double>(m_bins) * tau0_s;
    std::vector<double> x(y.size() + 1, 0.0);
    for (size_t k = 0; k < y.size(); ++k) x[k + 1] = x[k] + tau0_s * y[k];
    for (int64_t m : grid) {
        double sum = 0;
        int64_t terms = 0;
        if (bins_per_m * m <= m_bins) {
            for (int64_t k = 0; k + 2 * m <= m_bins; ++k) {
                const double d = x[k + 2 * m] - 2.0 * x[k + m] + x[k];
                sum += d * d;
                ++terms;
            }
        }
        s.sum_sq.push_back(sum);
        s.terms.push_back(terms);
    }
    return s;
}

std::vector<AllanPoint> Combine(const std::vector<SegmentSums>& segments, double tau0_s,
                                const std::vector<int64_t>& grid, int skip) {
    std::vector<AllanPoint> out;
    for (size_t j = 0; j < grid.size(); ++j) {
        const double m = static_cast<double>(grid[j]);
        double sum = 0, edf = 0;
        int64_t terms = 0;
        for (size_t s = 0; s < segments.size(); ++s) {
            if (static_cast<int>(s) == skip || j >= segments[s].terms.size()) continue;
            if (segments[s].terms[j] == 0) continue;
            sum += segments[s].sum_sq[j];
            terms += segments[s].terms[j];
            edf += SegmentEdf(static_cast<double>(segments[s].bins + 1), m);
        }
        if (terms == 0) continue;
        AllanPoint p;
        p.tau_s = m * tau0_s;
        p.terms = terms;
        p.edf = edf;
        const double avar = sum / (2.0 * p.tau_s * p.tau_s * static_cast<double>(terms));
        p.adev = std::sqrt(avar);
        p.adev_lo = std::sqrt(edf * avar / numeric::ChiSquareQuantile(0.8413, edf));
        p.adev_hi = std::sqrt(edf * avar / numeric::ChiSquareQuantile(0.1587, edf));
        out.push_back(p);
    }
    return out;
}

std::vector<SegmentSums> ScreenSegments(const std::vector<SegmentSums>& segments, double tau0_s,
                                        const std::vector<int64_t>& grid, double alpha,
                                        std::string& note) {
    std::vector<SegmentSums> kept = segments;
    const size_t max_out = segments.size() / 3;
    size_t out = 0;
    while (out < max_out && kept.size() >= 3) {
        int worst = -1;
        double worst_excess = 1.0;  // ratio over its threshold
        const double per_test = alpha / static_cast<double>(kept.size() * grid.size());
        for (size_t j = 0; j < grid.size(); ++j) {
            const double m = static_cast<double>(grid[j]);
            if (m * tau0_s < 1.0) continue;
            double sum = 0, edf = 0;
            int64_t terms = 0;
            for (const SegmentSums& g : kept)
                if (g.terms[j] > 0)
                    sum += g.sum_sq[j], terms += g.terms[j], edf += SegmentEdf(g.bins + 1, m);
            for (size_t k = 0; k < kept.size(); ++k) {
                const SegmentSums& g = kept[k];
                if (g.terms[j] == 0 || terms == g.terms[j]) continue;
                const double e_s = SegmentEdf(g.bins + 1, m), e_r = edf - e_s;
                const double ratio =
                    (g.sum_sq[j] / g.terms[j]) /
                    ((sum - g.sum_sq[j]) / static_cast<double>(terms - g.terms[j]));
                const double limit = std::max(4.0, numeric::FUpperQuantile(per_test, e_s, e_r));
                if (ratio / limit > worst_excess)
                    worst_excess = ratio / limit, worst = static_cast<int>(k);
            }
        }
        if (worst < 0) break;
        kept.erase(kept.begin() + worst);
        ++out;
    }
    if (out > 0)
        note = std::to_string(out) + " of " + std::to_string(segments.size()) +
               " still segments left out: their Allan variance is far above the others' (a "
               "disturbance inside them?)";
    return kept;
}

NoiseTerms FitTerms(const std::vector<SegmentSums>& segments, double tau0_s,
                    const std::vector<int64_t>& grid, double min_tau_s, double min_rrw_tau_s) {
    NoiseTerms t;
    const std::vector<AllanPoint> pts = FromTau(Combine(segments, tau0_s, grid), min_tau_s);
    const TermFit all = SolveTerms(pts, min_rrw_tau_s);
    if (!all.ok) {
        t.note = "too few Allan points above " + std::to_string(min_tau_s) + " s to fit";
        return t;
    }
    t.ok = true;
    t.arw = std::sqrt(all.theta[0]);
    t.bias = std::sqrt(all.theta[1]);
    t.rrw = std::sqrt(all.theta[2]);
    const char* labels[3] = {"angle random walk", "bias instability", "rate random walk"};
    for (int j = 0; j < 3; ++j) {
        if (all.active[j]) continue;
        const bool short_taus = j == 2 && pts.back().tau_s < min_rrw_tau_s;
        t.note += std::string(t.note.empty() ? "" : "; ") + labels[j] +
                  (short_taus ? " not fitted: tau reaches only " : " not resolved (set 0)") +
                  (short_taus ? std::to_string(static_cast<int>(pts.back().tau_s)) + " s" : "");
    }
    if (segments.size() >= 3) {
        double sums[3] = {0, 0, 0}, squares[3] = {0, 0, 0};
        int n = 0;
        for (size_t s = 0; s < segments.size(); ++s) {
            const TermFit f =
                SolveTerms(FromTau(Combine(segments, tau0_s, grid, static_cast<int>(s)), min_tau_s),
                           min_rrw_tau_s);
            if (!f.ok) continue;
            ++n;
            for (int j = 0; j < 3; ++j) {
                const double v = std::sqrt(f.theta[j]);
                sums[j] += v;
                squares[j] += v * v;
            }
        }
        double se[3];
        for (int j = 0; j < 3; ++j) {
            const double mean = n > 0 ? sums[j] / n : 0.0;
            se[j] = n > 1 ? std::sqrt(std::max(0.0, (n - 1.0) / n * (squares[j] - n * mean * mean)))
                          : kNaN;
        }
        t.arw_se = se[0], t.bias_se = se[1], t.rrw_se = se[2];
        t.note += std::string(t.note.empty() ? "" : "; ") + "standard errors: jackknife over " +
                  std::to_string(n) + " still segments";
    } else {
        // Delta method on the WLS covariance: se(sqrt(v)) = se(v) / (2 sqrt(v)).
        auto se = [&](int j) {
            const double v = all.theta[j];
            return v > 0 ? std::sqrt(all.cov(j, j)) / (2.0 * std::sqrt(v)) : kNaN;
        };
        t.arw_se = se(0), t.bias_se = se(1), t.rrw_se = se(2);
        t.note += std::string(t.note.empty() ? "" : "; ") +
                  "standard errors from the weighted fit (fewer than 3 segments for a jackknife; "
                  "they ignore the correlation between tau points and are too small)";
    }
    return t;
}

double WindowFlickerIntegral(double a) {
    // integral_a^inf sin^2(u)/u^3 du: Simpson in log u up to u = 1 (integrand ~ 1/u there), in u
    // up to 200, and the tail with sin^2 averaged to 1/2.
    auto f = [](double u) {
        const double s = std::sin(u);
        return s * s / (u * u * u);
    };
    auto simpson = [](auto g, double lo, double hi, int n) {
        const double h = (hi - lo) / n;
        double sum = g(lo) + g(hi);
        for (int i = 1; i < n; ++i) sum += g(lo + i * h) * (i % 2 ? 4.0 : 2.0);
        return sum * h / 3.0;
    };
    constexpr double kTailStart = 200.0;
    if (a >= kTailStart) return 1.0 / (4.0 * a * a);
    double total = 0.0;
    double lo = a;
    if (lo < 1.0) {
        total += simpson(
            [&](double s) {
                const double u = std::exp(s);
                return f(u) * u;
            },
            std::log(lo), 0.0, 2000);
        lo = 1.0;
    }
    total += simpson(f, lo, kTailStart, 40000);
    return total + 1.0 / (4.0 * kTailStart * kTailStart);
}

double SlowNoiseVariance(double bias, double rrw, double window_s, double span_s) {
    const double b = std::isfinite(bias) ? bias : 0.0;
    const double k = std::isfinite(rrw) ? rrw : 0.0;
    const double span = std::max(span_s, window_s);
    const double h = b * b / (2.0 * kLn2);
    return h * WindowFlickerIntegral(3.14159265358979323846 * window_s / span) + k * k * span / 6.0;
}

}  // namespace gyrocal::noise
