// The fleet view's numbers (store/format/fleet.hpp) on units with known curves: the lot's centre
// and spread, the unit outside it, a station's bias, valid ranges, too few units, the unit model
// read from a run's configuration, and drawable figures.
#include "store/format/fleet.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace gyrocal::format {
namespace {

// The standard normal quantile, by bisection on the CDF 0.5 erfc(-x / sqrt 2) (60 halvings of
// [-10, 10] reach 1e-17): places the units' offsets at evenly spaced quantiles.
double NormalQuantile(double p) {
    double lo = -10, hi = 10;
    for (int i = 0; i < 60; ++i) {
        const double mid = 0.5 * (lo + hi);
        (0.5 * std::erfc(-mid / std::sqrt(2.0)) < p ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
}

db::ModelRow Flat(const std::string& quantity, double value, double min_c = -40,
                  double max_c = 85) {
    db::ModelRow m;
    m.quantity = quantity;
    m.term_names = {"1", "dT"};
    m.coeffs = {value, 1e-3};  // the same slope for every unit: the spread is the level's
    m.covariance = {{0, 0}, {0, 0}};
    m.t0_c = 25;
    m.temp_min_c = min_c;
    m.temp_max_c = max_c;
    return m;
}

FleetUnit Unit(const std::string& id, const std::string& station, double offset_v,
               double sens = 0.0067, const std::string& model = "M") {
    FleetUnit u;
    u.sensor_id = id;
    u.model = model;
    u.station = station;
    u.run_id = "R-" + id;
    u.set.offset = Flat("offset_v", offset_v);
    u.set.sensitivity = Flat("sensitivity_v_per_dps", sens);
    u.set.sensitivity.coeffs[1] = 0;
    return u;
}

constexpr double kSigmaV = 0.004;  // [V] the lot's true spread of offsets
constexpr int kUnits = 20;

// kUnits units at evenly spaced quantiles of N(2.5, kSigmaV), alternating between stations A and
// B, plus one unit 8 sigma off.
std::vector<FleetUnit> Lot() {
    std::vector<FleetUnit> units;
    for (int i = 0; i < kUnits; ++i) {
        const double q = NormalQuantile((i + 0.5) / kUnits);
        units.push_back(Unit("U" + std::to_string(i), i % 2 ? "B" : "A", 2.5 + kSigmaV * q,
                             0.0067 * (1 + 0.002 * q)));
    }
    units.push_back(Unit("ODD", "A", 2.5 + 8 * kSigmaV));
    return units;
}

TEST(Fleet, TheLotsCentreAndSpreadAreRobustAndTheOddUnitIsOutside) {
    const auto groups = FleetSpread(Lot(), {});
    ASSERT_EQ(groups.size(), 1u);
    const FleetGroup& g = groups[0];
    ASSERT_TRUE(g.has_spread);
    const size_t at25 = 13;  // -40 + 13 * 5 = 25 degC
    ASSERT_DOUBLE_EQ(g.temps_c[at25], 25.0);
    EXPECT_EQ(g.offset.n[at25], 21u);
    // The median moves by at most half a quantile step for the odd unit (it is one of 21):
    // 0.07 sigma here; the MAD-based spread of quantile-placed values is sigma within 10 %.
    EXPECT_NEAR(g.offset.median[at25], 2.5, 0.1 * kSigmaV);
    EXPECT_NEAR(g.offset.spread[at25], kSigmaV, 0.1 * kSigmaV);
    // Only the odd unit: the lot's extremes sit at 1.96 sigma, the odd one at 8.
    ASSERT_EQ(g.outside.size(), 1u);
    EXPECT_EQ(g.units[g.outside[0].unit].sensor_id, "ODD");
    EXPECT_EQ(g.outside[0].quantity, "offset_v");
    EXPECT_NEAR(g.outside[0].worst_z, 8.0, 0.8);
}

TEST(Fleet, AStationWhoseUnitsSitHigherShowsItsBias) {
    auto units = Lot();
    for (auto& u : units)
        if (u.station == "B") u.set.offset.coeffs[0] += kSigmaV;  // station B reads 1 sigma high
    const auto g = FleetSpread(units, {}).at(0);
    ASSERT_EQ(g.stations.size(), 2u);
    EXPECT_EQ(g.stations[0].station, "A");
    // The median of the pooled lot sits between the stations: each is about half a sigma off it.
    EXPECT_LT(g.stations[0].offset_median_z, -0.2);
    EXPECT_GT(g.stations[1].offset_median_z, 0.2);
}

TEST(Fleet, OnlyTemperaturesInsideASetsValidRangeCountAndTooFewUnitsJudgeNothing) {
    auto units = Lot();
    units[0].set.offset = Flat("offset_v", 2.5, 0, 40);
    const auto g = FleetSpread(units, {.temps_c = {-40, 20}}).at(0);
    EXPECT_EQ(g.offset.n[0], 20u);  // U0's set does not reach -40
    EXPECT_EQ(g.offset.n[1], 21u);
    const std::vector<FleetUnit> three = {Unit("a", "A", 2.5), Unit("b", "A", 2.6),
                                          Unit("c", "A", 3.5)};
    const auto few = FleetSpread(three, {}).at(0);
    EXPECT_FALSE(few.has_spread);
    EXPECT_TRUE(few.outside.empty());
    EXPECT_NE(FleetText({few}, {}).find("no spread"), std::string::npos);
}

TEST(Fleet, UnitsAreGroupedByTheModelTheirRunsConfigurationGives) {
    EXPECT_EQ(UnitModelOf(R"({"unit_model":"myGyro613EB"})", "S1"), "myGyro613EB");
    EXPECT_EQ(UnitModelOf(R"({"unit_models":{"S1":"A","S2":"B"},"unit_model":"C"})", "S2"), "B");
    EXPECT_EQ(UnitModelOf(R"({"unit_models":{"S1":"A"},"unit_model":"C"})", "S9"), "C");
    EXPECT_EQ(UnitModelOf(R"({"preset":"610"})", "S1"), "preset 610");
    EXPECT_EQ(UnitModelOf("not json", "S1"), "unspecified");
    auto units = Lot();
    units.push_back(Unit("other", "A", 2.5, 0.0067, "N"));
    const auto groups = FleetSpread(units, {});
    ASSERT_EQ(groups.size(), 2u);
    EXPECT_EQ(groups[1].model, "N");
    EXPECT_EQ(groups[1].units.size(), 1u);
}

TEST(Fleet, FiguresAreDrawableAndNameTheUnitOutside) {
    const auto groups = FleetSpread(Lot(), {});
    const auto figures = FleetFigures(groups, {});
    ASSERT_EQ(figures.size(), 2u);
    for (const auto& f : figures) EXPECT_EQ(plot::Validate(f), "") << f.name;
    bool named = false;
    for (const auto& s : figures[0].series) named = named || s.title == "ODD (outside)";
    EXPECT_TRUE(named);
    const auto j = FleetJson(groups, {});
    EXPECT_EQ(j[0]["outside"][0]["sensor_id"], "ODD");
}

}  // namespace
}  // namespace gyrocal::format
