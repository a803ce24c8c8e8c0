// Bad configuration is refused with a message naming the option and the valid range.
#include "producers/sim/config.hpp"

#include <gtest/gtest.h>

#include <functional>

#include "producers/sim/builtin_profile.hpp"
#include "producers/sim/rig.hpp"

namespace gyrocal::sim {
namespace {

void ExpectRefused(const std::function<void(RigConfig&)>& mutate, const std::string& option) {
    RigConfig c = RigConfig::Defaults();
    mutate(c);
    try {
        Rig rig(c);
        ADD_FAILURE() << option << " was accepted";
    } catch (const ConfigError& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find(option), std::string::npos) << what;
        EXPECT_NE(what.find("valid"), std::string::npos) << what;
    }
}

TEST(SimConfig, DefaultsAreValid) { EXPECT_NO_THROW(RigConfig::Defaults().Validate()); }

TEST(SimConfig, OutOfRangeValuesAreRefused) {
    ExpectRefused([](RigConfig& c) { c.noise.noise_density_dps_rthz = -0.01; }, "--noise-density");
    ExpectRefused([](RigConfig& c) { c.noise.bias_instability_dps = NAN; },
                  "--bias-instability-dps");
    ExpectRefused([](RigConfig& c) { c.sample_rate_hz = 0.0; }, "--rate-hz");
    ExpectRefused([](RigConfig& c) { c.num_units = 0; }, "--units");
    ExpectRefused([](RigConfig& c) { c.sensor_ids = {"S01", "bad id"}; }, "--sensor-ids");
    ExpectRefused([](RigConfig& c) { c.sensor_ids = {"S01", "S01"}; }, "--sensor-ids");
    ExpectRefused([](RigConfig& c) { c.encoder.quadrature = 3; }, "--encoder-quadrature");
    ExpectRefused([](RigConfig& c) { c.adc.bits = 4; }, "--adc-bits");
    ExpectRefused([](RigConfig& c) { c.thermal.package_tau_s = 0.0; }, "--package-tau-s");
    ExpectRefused([](RigConfig& c) { c.thermal.start_temp_c = 120.0; }, "--start-temp-c");
    ExpectRefused([](RigConfig& c) { c.table.default_rate_dps = 400.0; }, "--table-rate-dps");
    ExpectRefused([](RigConfig& c) { c.supply.ripple_v = -1.0; }, "--supply-ripple-v");
}

TEST(SimConfig, UnknownPresetIsRefused) {
    EXPECT_THROW(PresetByName("612"), ConfigError);
    EXPECT_DOUBLE_EQ(PresetByName("613").sensitivity_v_per_dps, 0.0125);
    EXPECT_DOUBLE_EQ(PresetByName("613").range_dps, 150.0);
    EXPECT_DOUBLE_EQ(PresetByName("610").sensitivity_v_per_dps, 0.006);
}

TEST(SimConfig, ProfileParsing) {
    const ThermalConfig t;
    EXPECT_EQ(ParseProfile("-10,30,60", t), (std::vector<double>{-10.0, 30.0, 60.0}));
    EXPECT_THROW(ParseProfile("", t), ConfigError);
    EXPECT_THROW(ParseProfile("-10,,60", t), ConfigError);
    EXPECT_THROW(ParseProfile("-10,abc", t), ConfigError);
    EXPECT_THROW(ParseProfile("-10,300", t), ConfigError);
    EXPECT_THROW(ParseProfile("nan", t), ConfigError);
}

TEST(SimConfig, UnitIdsDefaultToS01Upward) {
    RigConfig c;
    c.num_units = 3;
    EXPECT_EQ(c.UnitIds(), (std::vector<std::string>{"S01", "S02", "S03"}));
    c.sensor_ids = {"A7"};
    EXPECT_EQ(c.UnitIds(), (std::vector<std::string>{"A7"}));
}

}  // namespace
}  // namespace gyrocal::sim
