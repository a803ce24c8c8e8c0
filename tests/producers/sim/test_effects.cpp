// Undeclared effects: each switched on changes the output by exactly its configured amount
// (measured against the same seed with it off), and switched off leaves the output bit-identical.
// Why exact: the runs share every random number (effects draw none), and the output chain is
// linear (offset + S * rate, then a linear low-pass) until the rails, which these runs never
// touch; so gyro_on - gyro_off must equal the low-passed effect term computed here from the
// configured magnitude and the physical state (die temperature, supply, rate). Tolerance 1e-12 V
// covers floating-point rounding of ~2.5 V values (ulp ~4e-16) through the filter. No ADC here:
// its quantization would round the difference to whole codes.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <functional>

#include "sim/rig.hpp"
#include "sim_test_support.hpp"

namespace gyrocal::sim {
namespace {

// A run with noise, a heat-up and cool-down (fast package so rates are large), and +-90 moves.
testing::Recorded Scenario(const EffectsConfig& effects) {
    RigConfig c = RigConfig::Defaults();
    c.seed = 42;
    c.num_units = 2;
    c.adc.bits = 0;
    c.thermal.ramp_c_per_min = 20.0;
    c.thermal.package_tau_s = 40.0;
    c.effects = effects;
    Rig rig(c);
    testing::RecordingSink sink;
    const int64_t s = c.start_utime;
    rig.ChamberCommand(1, 45.0, 0.0);
    rig.RunUntil(s + 200'000'000, sink);
    rig.TurntableCommand(1, 90.0, 0.0, 0.0);
    rig.RunUntil(s + 210'000'000, sink);
    rig.TurntableCommand(2, -90.0, 0.0, 0.0);
    rig.RunUntil(s + 220'000'000, sink);
    rig.ChamberCommand(2, 20.0, 0.0);
    rig.RunUntil(s + 500'000'000, sink);
    return sink.data;
}

// Low-passes `x` per unit with the rig's filter (alpha from 40 Hz at 100 Hz), first value kept.
std::vector<double> LowPass(const testing::Recorded& r, const std::vector<double>& x) {
    const double alpha = 1.0 - std::exp(-2.0 * M_PI * 40.0 / 100.0);
    std::vector<double> y(x.size());
    std::vector<double> state(2);
    std::vector<bool> primed(2, false);
    for (size_t i = 0; i < x.size(); ++i) {
        const int u = r.gyro[i].unit_index;
        state[u] = primed[u] ? state[u] + (x[i] - state[u]) * alpha : x[i];
        primed[u] = true;
        y[i] = state[u];
    }
    return y;
}

bool BitIdentical(const testing::Recorded& a, const testing::Recorded& b) {
    if (a.gyro.size() != b.gyro.size()) return false;
    for (size_t i = 0; i < a.gyro.size(); ++i) {
        const GyroReading &x = a.gyro[i], &y = b.gyro[i];
        if (std::memcmp(&x.gyro_v, &y.gyro_v, sizeof(double)) != 0 ||
            std::memcmp(&x.temp_v, &y.temp_v, sizeof(double)) != 0 ||
            std::memcmp(&x.supply_v, &y.supply_v, sizeof(double)) != 0 || x.seq != y.seq ||
            x.utime != y.utime)
            return false;
    }
    return true;
}

struct Case {
    const char* name;
    double value;
    // The effect's contribution to the analog output before the filter, from the physical state.
    std::function<double(const GyroTruth&, double t_s)> expected_v;
};

TEST(SimEffects, EachEffectChangesOutputByItsConfiguredAmountAndOffIsBitIdentical) {
    const testing::Recorded baseline = Scenario(EffectsConfig{});
    const double nominal_supply_v = RigConfig::Defaults().supply.nominal_v;
    const double warmup_tau_s = EffectsConfig{}.warmup_tau_s;
    const std::vector<Case> cases = {
        {"temp_rate", 0.002,
         [](const GyroTruth& t, double) { return 0.002 * t.die_rate_c_per_min; }},
        {"hysteresis", 0.004,
         [](const GyroTruth& t, double) { return 0.002 * t.hysteresis_branch; }},
        {"temp_cubic", 2e-8,
         [](const GyroTruth& t, double) { return 2e-8 * std::pow(t.die_c - 25.0, 3); }},
        {"supply", 0.05,
         [=](const GyroTruth& t, double) { return 0.05 * (t.supply_true_v - nominal_supply_v); }},
        {"warmup", 0.01,
         [=](const GyroTruth&, double ts) { return 0.01 * std::exp(-ts / warmup_tau_s); }},
        {"sf_asymmetry", 0.02,
         [](const GyroTruth& t, double) {
             const double rate = t.rate_true_dps + t.rate_noise_dps;
             if (t.rate_true_dps == 0.0) return 0.0;
             const double f = t.rate_true_dps > 0.0 ? 0.01 : -0.01;
             return t.sensitivity_v_per_dps * f * rate;
         }},
    };
    for (const Case& k : cases) {
        SCOPED_TRACE(k.name);
        // Off, explicitly set to 0: bit-identical to never mentioning it.
        EffectsConfig off;
        SetEffect(off, k.name, 0.0);
        EXPECT_TRUE(BitIdentical(Scenario(off), baseline));
        // On: the difference is the configured effect, through the filter.
        EffectsConfig on;
        SetEffect(on, k.name, k.value);
        const testing::Recorded with = Scenario(on);
        ASSERT_EQ(with.gyro.size(), baseline.gyro.size());
        std::vector<double> expected(with.gyro.size());
        const int64_t start = RigConfig::Defaults().start_utime;
        for (size_t i = 0; i < with.gyro.size(); ++i) {
            expected[i] = k.expected_v(with.truth[i], (with.gyro[i].utime - start) * 1e-6);
        }
        const std::vector<double> filtered = LowPass(with, expected);
        double max_err = 0.0, max_effect = 0.0;
        for (size_t i = 0; i < with.gyro.size(); ++i) {
            const double diff = with.gyro[i].gyro_v - baseline.gyro[i].gyro_v;
            max_err = std::max(max_err, std::abs(diff - filtered[i]));
            max_effect = std::max(max_effect, std::abs(diff));
            ASSERT_EQ(with.gyro[i].temp_v, baseline.gyro[i].temp_v) << "effects touch gyro_v only";
        }
        EXPECT_LT(max_err, 1e-12);
        EXPECT_GT(max_effect, 1e-4) << "the scenario exercises the effect (>= 0.1 mV)";
    }
}

TEST(SimEffects, HysteresisBranchesAreTheConfiguredDistanceApart) {
    EffectsConfig on;
    SetEffect(on, "hysteresis", 0.004);
    const testing::Recorded with = Scenario(on);
    const testing::Recorded off = Scenario(EffectsConfig{});
    // While heating well past the band the branch is +1; while cooling, -1: the offset terms
    // differ by the configured 4 mV at the same temperature.
    double heating = NAN, cooling = NAN;
    for (size_t i = 0; i < with.gyro.size(); ++i) {
        if (with.gyro[i].unit_index != 0) continue;
        const double d = with.truth[i].effect_offset_v;
        if (with.truth[i].die_c > 35.0 && with.truth[i].die_rate_c_per_min > 0.5) heating = d;
        if (with.truth[i].die_c < 35.0 && with.truth[i].die_rate_c_per_min < -0.5 &&
            with.truth[i].die_c > 30.0)
            cooling = d;
    }
    EXPECT_NEAR(heating - cooling, 0.004, 1e-12);
    (void)off;
}

TEST(SimEffects, BadEffectSpecificationsAreRefused) {
    EffectsConfig e;
    EXPECT_THROW(ParseEffect(e, "warmup"), ConfigError);
    EXPECT_THROW(ParseEffect(e, "warmup=abc"), ConfigError);
    EXPECT_THROW(ParseEffect(e, "nonsense=1"), ConfigError);
    EXPECT_THROW(ParseEffect(e, "supply=5"), ConfigError);  // 5 V/V: beyond the valid +-1
    ParseEffect(e, "temp_cubic=2e-8");
    EXPECT_DOUBLE_EQ(e.temp_cubic_v_per_c3, 2e-8);
    EXPECT_TRUE(e.AnyOn());
    try {
        ParseEffect(e, "nonsense=1");
    } catch (const ConfigError& err) {
        EXPECT_NE(std::string(err.what()).find("sf_asymmetry"), std::string::npos)
            << "lists the valid names: " << err.what();
    }
}

}  // namespace
}  // namespace gyrocal::sim
