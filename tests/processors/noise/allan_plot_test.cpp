// The Allan deviation as a figure (processors/noise/allan_plot): the numbers it tabulates, the
// asymptotes it marks, and that gnuplot draws it on log axes (skipped, saying so, without
// gnuplot). The curve is built from known N, B, K, so every tabulated value has an exact truth
// (tolerances are rounding only: the data file keeps 9 significant digits, checked at 1e-12
// relative on the in-memory table).
#include "processors/noise/allan_plot.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <regex>
#include <set>

#include "processors/plot/gnuplot/gnuplot.hpp"

namespace gyrocal::noise {
namespace {

constexpr double kN = 2.4e-4, kB = 5e-5, kK = 2e-6;  // V/rtHz, V, V/rts
constexpr double kSens = 0.006;                      // V/(deg/s)

double Adev(double tau, double n, double b, double k) {
    return std::sqrt(n * n / tau + b * b + k * k * tau / 3);
}

AllanPlotInput Curve(double k_v_rts) {
    AllanPlotInput in;
    in.sensor_id = "U7";
    for (double tau = 0.1; tau < 2000; tau *= 2) {
        const double a = Adev(tau, kN, kB, k_v_rts);
        in.tau_s.push_back(tau);
        in.adev_v.push_back(a);
        in.adev_lo_v.push_back(0.9 * a);
        in.adev_hi_v.push_back(1.1 * a);
    }
    in.arw_v_rthz = kN, in.bias_v = kB, in.rrw_v_rts = k_v_rts;
    in.sensitivity_v_per_dps = kSens;
    return in;
}

const plot::Series* Titled(const plot::Figure& f, const std::string& start) {
    for (const plot::Series& s : f.series)
        if (s.title.rfind(start, 0) == 0) return &s;
    return nullptr;
}

TEST(AllanPlot, TabulatesTheFitAndItsThreeAsymptotesInDegreesPerSecondOnLogAxes) {
    // GIVEN a curve of known N, B, K and the unit's sensitivity
    const plot::Figure f = MakeAllanPlot(Curve(kK));
    // THEN the figure is drawable, log-log, in deg/s
    EXPECT_EQ(plot::Validate(f), "");
    EXPECT_TRUE(f.log_x && f.log_y);
    EXPECT_EQ(f.name, "U7_allan");
    EXPECT_NE(f.ylabel.find("deg/s"), std::string::npos);
    // AND each row carries the measured point, the fit and the asymptotes N/sqrt(tau), B,
    // K sqrt(tau/3), all divided by the sensitivity
    const plot::Table& t = f.tables.at(0);
    ASSERT_EQ(t.rows.size(), Curve(kK).tau_s.size());
    const double n = kN / kSens, b = kB / kSens, k = kK / kSens;
    for (const auto& r : t.rows) {
        const double tau = r[0];
        EXPECT_NEAR(r[1], Adev(tau, n, b, k), 1e-12 * r[1]);
        EXPECT_NEAR(r[4], Adev(tau, n, b, k), 1e-12 * r[4]);
        EXPECT_NEAR(r[5], n / std::sqrt(tau), 1e-12 * r[5]);
        EXPECT_NEAR(r[6], b, 1e-12 * b);
        EXPECT_NEAR(r[7], k * std::sqrt(tau / 3), 1e-12 * r[7]);
    }
    // AND the three slopes are marked with their values
    ASSERT_NE(Titled(f, "slope -1/2: N = 0.04 deg/s/sqrt(Hz)"), nullptr) << f.series[3].title;
    ASSERT_NE(Titled(f, "slope 0: B = 0.00833 deg/s"), nullptr);
    ASSERT_NE(Titled(f, "slope +1/2: K = 0.000333 deg/s/sqrt(s)"), nullptr);
}

TEST(AllanPlot, ATermNotFittedHasNoAsymptoteAndVoltsWithoutASensitivity) {
    // GIVEN a run too short for the rate random walk (K = 0) and no fitted sensitivity
    AllanPlotInput in = Curve(0.0);
    in.sensitivity_v_per_dps.reset();
    const plot::Figure f = MakeAllanPlot(in);
    EXPECT_EQ(plot::Validate(f), "");
    // THEN no +1/2 line is claimed, the other two are, in volts
    EXPECT_EQ(Titled(f, "slope +1/2"), nullptr);
    ASSERT_NE(Titled(f, "slope -1/2: N = 0.00024 V/sqrt(Hz)"), nullptr);
    ASSERT_NE(Titled(f, "slope 0: B = 5e-05 V"), nullptr);
    EXPECT_NE(f.ylabel.find("[V]"), std::string::npos);
    // AND with no term fitted at all only the measured points (and their band) are drawn
    in.arw_v_rthz = NAN, in.bias_v = 0;
    EXPECT_EQ(MakeAllanPlot(in).series.size(), 2u);
}

// gnuplot draws it: the SVG's tic labels are decades (log axes). The lowest value drawn is the
// rate random walk's asymptote at the shortest tau (K sqrt(0.1/3) = 6.1e-5 deg/s), the highest the
// band at 0.1 s (0.14): gnuplot widens a log range to whole decades, 1e-5..1, and a margin on top
// (as on linear axes) would add a decade more on each side (1e-6 .. 10).
TEST(AllanPlot, GnuplotDrawsItOnLogAxes) {
    const std::string gnuplot = plot::gnuplot::FindOnPath("gnuplot");
    if (gnuplot.empty())
        GTEST_SKIP() << "gnuplot is not installed (Debian gnuplot-nox; tools/run.sh installs it)";
    const std::vector<std::string> svg =
        plot::gnuplot::DrawInlineSvgs(gnuplot, {MakeAllanPlot(Curve(kK))});
    ASSERT_EQ(svg.size(), 1u);
    std::set<std::string> labels;
    const std::regex text_re(">\\s*([0-9.e+-]+)\\s*<");
    for (auto it = std::sregex_iterator(svg[0].begin(), svg[0].end(), text_re);
         it != std::sregex_iterator(); ++it)
        labels.insert((*it)[1]);
    for (const char* decade : {"1e-05", "0.0001", "0.001", "0.01", "0.1", "1", "1000"})
        EXPECT_EQ(labels.count(decade), 1u) << "no tic label " << decade;
    EXPECT_EQ(labels.count("1e-06"), 0u) << "the y range reaches a decade below the data";
    for (const char* linear : {"0.02", "0.05", "0.2", "500"})
        EXPECT_EQ(labels.count(linear), 0u)
            << "a linear tic on what should be a log axis: " << linear;
    EXPECT_NE(svg[0].find("slope +1/2"), std::string::npos);
}

}  // namespace
}  // namespace gyrocal::noise
