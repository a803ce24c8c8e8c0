#include "processors/numeric/distributions.hpp"

#include <cmath>
#include <functional>

namespace gyrocal::numeric {

namespace {

constexpr double kTiny = 1e-300;

// Continued fraction of the regularised incomplete beta (modified Lentz), valid for
// x < (a + 1) / (a + b + 2); the caller uses the symmetry otherwise.
double BetaContinuedFraction(double a, double b, double x) {
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

// I_x(a, b).
double RegularisedBeta(double a, double b, double x) {
    if (x <= 0.0) return 0.0;
    if (x >= 1.0) return 1.0;
    const double front = std::exp(std::lgamma(a + b) - std::lgamma(a) - std::lgamma(b) +
                                  a * std::log(x) + b * std::log1p(-x));
    if (x < (a + 1.0) / (a + b + 2.0)) return front * BetaContinuedFraction(a, b, x) / a;
    return 1.0 - front * BetaContinuedFraction(b, a, 1.0 - x) / b;
}

// P(a, x), the regularised lower incomplete gamma: series for x < a + 1, else continued fraction.
double RegularisedGammaP(double a, double x) {
    if (x <= 0.0) return 0.0;
    const double log_front = a * std::log(x) - x - std::lgamma(a);
    if (x < a + 1.0) {
        double term = 1.0 / a, sum = term;
        for (int n = 1; n < 1000; ++n) {
            term *= x / (a + n);
            sum += term;
            if (std::abs(term) < std::abs(sum) * 1e-16) break;
        }
        return sum * std::exp(log_front);
    }
    double b = x + 1.0 - a, c = 1.0 / kTiny, d = 1.0 / b, h = d;
    for (int i = 1; i < 1000; ++i) {
        const double an = -i * (i - a);
        b += 2.0;
        d = an * d + b;
        if (std::abs(d) < kTiny) d = kTiny;
        c = b + an / c;
        if (std::abs(c) < kTiny) c = kTiny;
        d = 1.0 / d;
        h *= d * c;
        if (std::abs(d * c - 1.0) < 1e-16) break;
    }
    return 1.0 - std::exp(log_front) * h;
}

// The x > 0 where the decreasing function tail(x) crosses target (bisection on log x).
double SolveDecreasing(const std::function<double(double)>& tail, double target) {
    double lo = 1e-12, hi = 1e12;
    for (int k = 0; k < 300; ++k) {
        const double mid = std::sqrt(lo * hi);
        (tail(mid) > target ? lo : hi) = mid;
        if (hi / lo < 1.0 + 1e-12) break;
    }
    return std::sqrt(lo * hi);
}

}  // namespace

double FUpperTail(double x, double d1, double d2) {
    if (x <= 0.0) return 1.0;
    return RegularisedBeta(0.5 * d2, 0.5 * d1, d2 / (d2 + d1 * x));
}

double FUpperQuantile(double upper_tail, double d1, double d2) {
    return SolveDecreasing([&](double x) { return FUpperTail(x, d1, d2); }, upper_tail);
}

double TwoSidedTQuantile(double two_sided_tail, double nu) {
    if (nu <= 0.0 || nu > 1e7) {
        // |N(0,1)| > x has probability erfc(x / sqrt 2).
        return SolveDecreasing([](double x) { return std::erfc(x / std::sqrt(2.0)); },
                               two_sided_tail);
    }
    // t_nu^2 = F(1, nu).
    return std::sqrt(FUpperQuantile(two_sided_tail, 1.0, nu));
}

double ChiSquareLowerTail(double x, double nu) { return RegularisedGammaP(0.5 * nu, 0.5 * x); }

double ChiSquareQuantile(double lower_tail, double nu) {
    return SolveDecreasing([&](double x) { return 1.0 - ChiSquareLowerTail(x, nu); },
                           1.0 - lower_tail);
}

}  // namespace gyrocal::numeric
