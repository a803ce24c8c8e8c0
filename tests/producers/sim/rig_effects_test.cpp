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
#include <cstdio>
#include <cstring>
#include <functional>

#include "producers/sim/rig.hpp"
#include "producers/sim/truth.hpp"
#include "tests/producers/sim/sim_test_support.hpp"

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
    testing::Run(rig, sink, c.start_utime, {45.0, 200, 10, 20.0, 500});
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

RigConfig OneUnitConfig() {
    RigConfig c = RigConfig::Defaults();
    c.num_units = 1;
    return c;
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
        // Outside the analysis' candidate list:
        {"aging", 0.002, [](const GyroTruth&, double ts) { return 0.002 * ts / 3600.0; }},
        {"compressor", 0.001,
         [](const GyroTruth&, double ts) { return 0.001 * std::sin(2.0 * M_PI * ts / 600.0); }},
        {"gsens", 0.05,
         [](const GyroTruth& t, double) {
             return 0.05 * std::sin(2.0 * M_PI / 180.0) *
                    std::cos(t.table_angle_deg * M_PI / 180.0);
         }},
        // Candidate-shaped with another shape:
        {"hysteresis_smooth", 0.004,
         [](const GyroTruth& t, double) { return 0.002 * t.hysteresis_smooth_branch; }},
        {"warmup2", 0.003,
         [](const GyroTruth&, double ts) { return 0.003 * std::exp(-ts / 1500.0); }},
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

// The smooth branch, recomputed here from the die temperatures the truth reports: it follows
// db/d|dT| = (sign(dT) - b) / travel exactly (rounding only, 1e-12), it turns over gradually after
// the reversal (not the play operator's straight ramp), and the branches end the configured
// value apart once the travel since the reversal is many travels long.
TEST(SimEffects, SmoothHysteresisTurnsOverExponentiallyInTheTravel) {
    EffectsConfig on;
    SetEffect(on, "hysteresis_smooth", 0.004);
    SetEffect(on, "hysteresis_travel_c", 3.0);
    const testing::Recorded with = Scenario(on);
    double b = 0.0, prev_die = NAN, max_err = 0.0;
    double top_c = -1e9, b_top = NAN;
    bool checked_one_travel = false;
    for (size_t i = 0; i < with.gyro.size(); ++i) {
        if (with.gyro[i].unit_index != 0) continue;
        const GyroTruth& t = with.truth[i];
        if (!std::isnan(prev_die) && t.die_c != prev_die) {
            const double d = t.die_c - prev_die;
            const double target = d > 0.0 ? 1.0 : -1.0;
            b = target + (b - target) * std::exp(-std::fabs(d) / 3.0);
        }
        prev_die = t.die_c;
        max_err = std::max(max_err, std::fabs(b - t.hysteresis_smooth_branch));
        max_err = std::max(max_err, std::fabs(t.effect_offset_v - 0.002 * b));
        if (t.die_c > top_c) top_c = t.die_c, b_top = b;
        // One travel below the top while cooling: from b_top toward -1 by 1 - 1/e of the way
        // (up to the small jitter of the air noise in the travel), where a play operator of the
        // same width would still be on a straight line.
        if (!checked_one_travel && t.die_c < top_c - 3.0 && t.die_rate_c_per_min < 0.0) {
            checked_one_travel = true;
            EXPECT_NEAR(t.hysteresis_smooth_branch, -1.0 + (b_top + 1.0) / M_E, 0.02);
        }
    }
    EXPECT_LT(max_err, 1e-12);
    EXPECT_TRUE(checked_one_travel);
    EXPECT_GT(b_top, 0.99) << "20 degC of heating is ~7 travels: the heating branch";
}

// The angle the gsens effect uses is the table's: the encoder's true angle at the same time.
TEST(SimEffects, GsensFollowsTheTableAngle) {
    EffectsConfig on;
    SetEffect(on, "gsens", 0.05);
    SetEffect(on, "tilt_deg", 5.0);
    const testing::Recorded with = Scenario(on);
    size_t e = 0, compared = 0;
    double at_90 = NAN, at_0 = NAN;
    for (size_t i = 0; i < with.gyro.size(); ++i) {
        while (e < with.encoder.size() && with.encoder[e].utime < with.gyro[i].utime) ++e;
        ASSERT_LT(e, with.encoder.size());
        ASSERT_EQ(with.encoder[e].utime, with.gyro[i].utime) << "same 100 Hz grid";
        EXPECT_EQ(with.truth[i].table_angle_deg, with.encoder[e].true_angle_deg);
        ++compared;
        if (with.gyro[i].unit_index != 0) continue;
        if (with.truth[i].table_angle_deg == 90.0) at_90 = with.truth[i].effect_offset_v;
        if (with.truth[i].table_angle_deg == 0.0) at_0 = with.truth[i].effect_offset_v;
    }
    EXPECT_GT(compared, 1000u);
    // At 0 deg gravity's in-plane part sin(5 deg) g acts fully, at 90 deg not at all.
    EXPECT_NEAR(at_0 - at_90, 0.05 * std::sin(5.0 * M_PI / 180.0), 1e-15);
}

TEST(SimEffects, ShapesAloneChangeNothingAndBadShapesAreRefused) {
    const testing::Recorded baseline = Scenario(EffectsConfig{});
    EffectsConfig shapes;
    for (const char* s : {"compressor_period_s=900", "tilt_deg=10", "hysteresis_travel_c=1",
                          "warmup2_tau_s=99", "warmup_tau_s=4000", "hysteresis_width_c=5"})
        ParseEffect(shapes, s);
    EXPECT_FALSE(shapes.AnyOn());
    EXPECT_TRUE(BitIdentical(Scenario(shapes), baseline)) << "a shape without its magnitude";
    // Each bad value is refused with the option's name and what is valid.
    const std::vector<std::pair<std::string, std::string>> bad = {
        {"compressor_period_s=0", "compressor_period_s"},
        {"tilt_deg=91", "tilt_deg"},
        {"tilt_deg=0", "tilt_deg"},
        {"hysteresis_travel_c=-1", "hysteresis_travel_c"},
        {"warmup2_tau_s=nan", "warmup2_tau_s"},
        {"aging=5", "aging"},
        {"compressor=1", "compressor"},
        {"gsens=x", "gsens=x"},
        {"warmup2=", "NAME=VALUE"},
        {"hysteresis_smooth=inf", "hysteresis_smooth"}};
    for (const auto& [text, name] : bad) {
        EffectsConfig e;
        try {
            ParseEffect(e, text);
            ADD_FAILURE() << text << " was accepted";
        } catch (const ConfigError& err) {
            const std::string what = err.what();
            EXPECT_NE(what.find(name), std::string::npos) << what;
            // A value out of range says the valid range; a malformed one says the form.
            EXPECT_TRUE(what.find("valid:") != std::string::npos ||
                        what.find("not a number") != std::string::npos ||
                        what.find("expected NAME=VALUE") != std::string::npos)
                << what;
        }
    }
    try {
        EffectsConfig e;
        ParseEffect(e, "tilt=3");
        ADD_FAILURE() << "tilt=3 accepted";
    } catch (const ConfigError& err) {
        const std::string what = err.what();
        for (const char* n : {"aging", "compressor", "gsens", "hysteresis_smooth", "warmup2",
                              "tilt_deg", "compressor_period_s", "warmup2_tau_s"})
            EXPECT_NE(what.find(n), std::string::npos) << n << ": " << what;
    }
    // A configuration built in code is refused the same way by Validate.
    RigConfig c = RigConfig::Defaults();
    c.effects.tilt_deg = 95.0;
    EXPECT_THROW(c.Validate(), ConfigError);
}

// The truth file says which effects are on, their shapes, and which the analysis has no
// candidate for.
TEST(SimEffects, TruthRecordsTheNewEffectsAndTheirStatus) {
    RigConfig c = OneUnitConfig();
    for (const char* s :
         {"aging=0.001", "compressor=0.0005", "compressor_period_s=700", "gsens=0.02", "tilt_deg=4",
          "hysteresis_smooth=0.002", "warmup2=0.003", "warmup2_tau_s=2000"})
        ParseEffect(c.effects, s);
    const Rig rig(c);
    const nlohmann::json j = TruthJson(rig).at("effects");
    EXPECT_EQ(j.at("aging").at("value"), 0.001);
    EXPECT_EQ(j.at("aging").at("unit"), "V/h");
    EXPECT_EQ(j.at("compressor").at("period_s"), 700.0);
    EXPECT_EQ(j.at("gsens").at("tilt_deg"), 4.0);
    EXPECT_EQ(j.at("hysteresis_smooth").at("travel_c"), 3.0);
    EXPECT_EQ(j.at("warmup2").at("tau_s"), 2000.0);
    for (const char* n : {"aging", "compressor", "gsens"}) {
        EXPECT_TRUE(j.at(n).at("on").get<bool>()) << n;
        EXPECT_EQ(j.at(n).at("analysis"), "outside the list") << n;
    }
    EXPECT_EQ(j.at("warmup").at("analysis"), "candidate");
    EXPECT_FALSE(j.at("warmup").at("on").get<bool>());
}

namespace measured {

// A still unit at the chamber's start temperature for 1200 s with every noise of the rig on
// (rate noise, bias instability, rate random walk, LPF, 16-bit ADC): the effect must show in
// the recorded gyro_v alone, as a regression on its shape, within the noise.
std::vector<GyroReading> StillRun(const EffectsConfig& effects, uint64_t noise_seed) {
    RigConfig c = RigConfig::Defaults();
    c.seed = 5;
    c.noise_seed = noise_seed;
    c.num_units = 1;
    c.effects = effects;
    Rig rig(c);
    testing::RecordingSink sink;
    rig.RunUntil(c.start_utime + 1'200'000'000, sink);
    return sink.data.gyro;
}

// Least-squares coefficient of `shape(t_s)` in gyro_v with a constant beside it.
double Coefficient(const std::vector<GyroReading>& g, const std::function<double(double)>& shape) {
    double n = 0, sx = 0, sy = 0, sxx = 0, sxy = 0;
    for (const GyroReading& r : g) {
        const double x = shape((r.utime - g.front().utime) * 1e-6);
        n += 1, sx += x, sy += r.gyro_v, sxx += x * x, sxy += x * r.gyro_v;
    }
    return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

// The effect's coefficient measured on its run, against the configured value; the tolerance is
// 5 standard deviations of the same coefficient measured on 8 runs without the effect (other
// noise seeds): the noise's own scatter for this shape and length of data, slow noise included.
void ExpectMeasured(const char* name, double value, const std::function<double(double)>& shape,
                    const char* shape_setting = nullptr) {
    EffectsConfig on;
    SetEffect(on, name, value);
    if (shape_setting) ParseEffect(on, shape_setting);
    std::vector<double> noise;
    for (uint64_t s = 101; s <= 108; ++s) noise.push_back(Coefficient(StillRun({}, s), shape));
    double ss = 0;
    for (double x : noise) ss += x * x;  // about 0: no effect
    const double sd = std::sqrt(ss / noise.size());
    const double measured = Coefficient(StillRun(on, 100), shape);
    std::printf("[ measured ] %s: %.4g against %.4g configured, noise sd %.3g\n", name, measured,
                value, sd);
    EXPECT_NEAR(measured, value, 5.0 * sd) << name;
    EXPECT_LT(5.0 * sd, 0.2 * std::fabs(value)) << "the run resolves the effect";
}

TEST(SimEffectsMeasured, AgingIsASlopeInTime) {
    ExpectMeasured("aging", 0.01, [](double t) { return t / 3600.0; });
}

TEST(SimEffectsMeasured, CompressorIsASineOfItsPeriod) {
    ExpectMeasured("compressor", 0.001, [](double t) { return std::sin(2.0 * M_PI * t / 600.0); });
}

TEST(SimEffectsMeasured, Warmup2IsAnExponentialOfItsTimeConstant) {
    // tau 200 s: a 1200 s run sees the whole transient (at 1500 s it would be nearly a line).
    ExpectMeasured(
        "warmup2", 0.003, [](double t) { return std::exp(-t / 200.0); }, "warmup2_tau_s=200");
}

}  // namespace measured

}  // namespace
}  // namespace gyrocal::sim
