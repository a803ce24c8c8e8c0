// Each limit measured on models and points whose answer is known in closed form, and the
// outcome rules: fail, pass, not evaluated (never a silent pass).
#include "processors/acceptance/evaluate.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace gyrocal::acceptance {
namespace {

model::Model Offset() {
    // 2.5 + 3e-4 dT + 5e-6 dT^2 about 25 degC on -40..85 degC: minimum 2.4955 V at -5 degC (dT
    // -30, on the 0.625 degC grid), maximum 2.536 V at 85 degC: a change of 0.0405 V.
    model::Model m;
    m.quantity = model::kOffsetQuantity;
    m.term_names = {"1", "dT", "dT^2"};
    m.coeffs = Eigen::Vector3d(2.5, 3e-4, 5e-6);
    m.covariance = Eigen::Matrix3d::Identity() * 1e-12;
    m.t0_c = 25;
    m.temp_min_c = -40;
    m.temp_max_c = 85;
    m.method = "wls";
    return m;
}

model::Model Sensitivity(double s0 = 0.005, double s1 = 1e-5) {
    model::Model m;
    m.quantity = model::kSensitivityQuantity;
    m.term_names = {"1", "dT"};
    m.coeffs = Eigen::Vector2d(s0, s1);
    m.covariance = Eigen::Vector2d(5e-6 * 5e-6, 1e-7 * 1e-7).asDiagonal();
    m.t0_c = 25;
    m.temp_min_c = -40;
    m.temp_max_c = 85;
    m.method = "wls";
    return m;
}

model::ModelInputs At(double t) {
    model::ModelInputs in;
    in.temp_c = t;
    return in;
}

// Five plateaus whose residuals are the given multiples of their floor sigma.
UnitEvidence Unit(const std::vector<double>& residual_sigmas, double slow_dps) {
    UnitEvidence u;
    u.sensor_id = "S01";
    u.has_calibration = true;
    u.offset = Offset();
    u.sensitivity = Sensitivity(0.005, 0.0);  // flat: slow noise in volts is 0.005 * slow_dps
    u.plateau_slow_noise_dps = slow_dps;
    const double sem = 3e-5;
    const double sigma = std::hypot(sem, slow_dps * 0.005);
    const double temps[] = {-40, -10, 25, 55, 85};
    for (size_t i = 0; i < residual_sigmas.size(); ++i) {
        const double fit = model::Evaluate(u.offset, At(temps[i]), model::RangePolicy::kClip).value;
        u.plateaus.push_back({temps[i], fit + residual_sigmas[i] * sigma, sem});
    }
    u.n_plateaus = static_cast<int>(u.plateaus.size());
    u.n_turns = 10;
    return u;
}

TEST(Measures, OffsetChangeIsTheSpanOfTheCurveInDegPerS) {
    const Measure m = OffsetChangeDps(Offset(), Sensitivity(0.005, 0.0));
    EXPECT_NEAR(m.value, 0.0405 / 0.005, 1e-9);  // exact: the extremes are grid points
}

TEST(Measures, SensitivityUncertaintyIsTheWorstRelativeSigmaOverTheRange) {
    // sigma(S) = sqrt(var0 + dT^2 var1) grows and S = s0 + s1 dT shrinks towards -40 degC (dT -65).
    const double expected = 100.0 * std::sqrt(25e-12 + 65.0 * 65.0 * 1e-14) / (0.005 - 65e-5);
    EXPECT_NEAR(MaxSensitivityRelUncertaintyPct(Sensitivity()).value, expected, 1e-9);
    model::Model nominal = Sensitivity();
    nominal.term_names = {"1"};
    nominal.coeffs = Eigen::VectorXd::Constant(1, 0.006);
    nominal.covariance = Eigen::MatrixXd::Constant(1, 1, NAN);
    nominal.method = "nominal";
    const Measure m = MaxSensitivityRelUncertaintyPct(nominal);
    EXPECT_TRUE(std::isnan(m.value));
    EXPECT_NE(m.note.find("no turn was fitted"), std::string::npos) << m.note;
}

TEST(Measures, ResidualOverFloorIsSqrtChi2PerDofWithTheSlowNoiseInTheFloor) {
    // chi2 = 1 + 1 + 4 + 4 + 0 = 10 on 5 - 3 = 2 dof.
    EXPECT_NEAR(ResidualOverFloor(Unit({1, -1, 2, -2, 0}, 0.0)).value, std::sqrt(5.0), 1e-6);
    EXPECT_NEAR(ResidualOverFloor(Unit({1, -1, 2, -2, 0}, 0.015)).value, std::sqrt(5.0), 1e-6);
    // Three plateaus for three terms: no degree of freedom, nothing to judge by.
    const Measure none = ResidualOverFloor(Unit({0.5, 0.5, 0.5}, 0.0));
    EXPECT_TRUE(std::isnan(none.value));
    EXPECT_NE(none.note.find("no degree of freedom"), std::string::npos) << none.note;
}

TEST(Evaluate, EachLimitPassesOrFailsOnItsMeasure) {
    Limits l;
    l.max_residual_rms_over_floor = 2.0;  // measured sqrt(5) = 2.24: fail
    l.max_offset_change_dps = 9.0;        // measured 8.1: pass
    l.min_plateaus = 5;                   // 5: pass
    l.min_turns = 12;                     // 10: fail
    const UnitVerdict v = Evaluate(l, Unit({1, -1, 2, -2, 0}, 0.0));
    ASSERT_EQ(v.checks.size(), 4u);
    EXPECT_EQ(v.checks[0].key, "max_residual_rms_over_floor");
    EXPECT_EQ(v.checks[0].outcome, Outcome::kFail);
    EXPECT_EQ(v.checks[1].outcome, Outcome::kPass);
    EXPECT_NEAR(v.checks[1].measured, 8.1, 1e-9);
    EXPECT_EQ(v.checks[2].outcome, Outcome::kPass);
    EXPECT_EQ(v.checks[3].outcome, Outcome::kFail);
    EXPECT_EQ(v.outcome, Outcome::kFail);
    const std::string s = Summary(v);
    EXPECT_NE(s.find("S01: FAIL: max_residual_rms_over_floor 2.24 > 2 1"), std::string::npos) << s;
    EXPECT_NE(s.find("min_turns 10 < 12 count"), std::string::npos) << s;
    EXPECT_EQ(s.find("max_offset_change_dps"), std::string::npos)
        << "a passing limit is not listed: " << s;
    l.max_residual_rms_over_floor = 2.5;
    l.min_turns = 10;
    EXPECT_EQ(Evaluate(l, Unit({1, -1, 2, -2, 0}, 0.0)).outcome, Outcome::kPass);
    EXPECT_EQ(Summary(Evaluate(l, Unit({1, -1, 2, -2, 0}, 0.0))), "S01: pass");
}

// The limit reads the analysis' stored outcome; the headline is only the explanation, so any
// wording of it (even one that starts like an older "no missing effect") decides nothing.
TEST(Evaluate, NoUnexplainedResidualReadsTheAnalysisOutcomeAndIsNeverASilentPass) {
    Limits l;
    l.no_unexplained_residual = true;
    UnitEvidence u = Unit({0, 0, 0, 0, 0}, 0.0);
    EXPECT_EQ(Evaluate(l, u).outcome, Outcome::kNotEvaluated);  // no analysis
    EXPECT_NE(Evaluate(l, u).checks[0].note.find("gyrocal analyze"), std::string::npos);
    struct Case {
        const char* outcome;
        const char* headline;
        Outcome expected;
    };
    const Case cases[] = {
        {"adequate", "no missing effect: adequate, held-out residual 0.1 mV", Outcome::kPass},
        {"explained", "missing effect: temp_rate, explained: held-out residual 0.1 mV",
         Outcome::kPass},
        {"partly explained", "missing effect: supply, partly explained: 3x the bound",
         Outcome::kFail},
        {"unexplained residual", "missing effect (unexplained residual): 4x the bound",
         Outcome::kFail},
        // Decided by the outcome, not the words: an unexplained outcome whose headline reads like
        // a pass still fails.
        {"unexplained residual", "no missing effect", Outcome::kFail},
        {"not testable", "not testable: 4 of 6 candidates could not be tested",
         Outcome::kNotEvaluated},
        // Two shapes the data cannot tell apart: a set carrying the wrong one fails wherever
        // they differ, so the unit fails until the named measurement separates them.
        {"ambiguous",
         "ambiguous: hysteresis vs step [time]: to separate: a setpoint approached "
         "from above before and after the event",
         Outcome::kFail},
    };
    u.analysis_stored_set = true;  // an analysis that added terms stored its extended set
    for (const Case& c : cases) {
        u.analysis_verdict = c.headline;
        u.analysis_outcome = c.outcome;
        const UnitVerdict v = Evaluate(l, u);
        ASSERT_EQ(v.checks.size(), 1u);
        EXPECT_EQ(v.checks[0].outcome, c.expected) << c.outcome;
        EXPECT_NE(v.checks[0].measured_text.find(c.outcome), std::string::npos)
            << v.checks[0].measured_text;
        if (c.expected == Outcome::kFail) {
            EXPECT_NE(v.checks[0].note.find(c.headline), std::string::npos) << v.checks[0].note;
        }
    }
    // Explained by terms that no stored set carries: the unit is not served by what was stored.
    u.analysis_outcome = "explained";
    u.analysis_stored_set = false;
    const Check ex = Evaluate(l, u).checks[0];
    EXPECT_EQ(ex.outcome, Outcome::kFail);
    EXPECT_NE(ex.note.find("no stored set carries"), std::string::npos) << ex.note;
    // Not testable says what to measure.
    u.analysis_outcome = "not testable";
    u.analysis_to_test = {"temp_cubic: dwells at 5 or more temperatures spread over the range"};
    const Check nt = Evaluate(l, u).checks[0];
    EXPECT_NE(nt.note.find("to test it: temp_cubic: dwells at 5 or more temperatures"),
              std::string::npos)
        << nt.note;
    EXPECT_NE(Summary(Evaluate(l, u)).find("not evaluated (the analysis could not test this unit"),
              std::string::npos);
}

// Bad input from an old or foreign database: an analysis stored without an outcome (before
// outcomes existed) or with one this version does not know is "not evaluated", and the note names
// it; never a pass read from the headline.
TEST(Evaluate, AMissingOrUnknownStoredOutcomeIsNotEvaluatedAndNamed) {
    Limits l;
    l.no_unexplained_residual = true;
    UnitEvidence u = Unit({0, 0, 0, 0, 0}, 0.0);
    u.analysis_verdict = "no missing effect";
    const Check old = Evaluate(l, u).checks[0];
    EXPECT_EQ(old.outcome, Outcome::kNotEvaluated);
    EXPECT_NE(old.note.find("without an outcome"), std::string::npos) << old.note;
    EXPECT_NE(old.note.find("gyrocal analyze RUN again"), std::string::npos) << old.note;
    u.analysis_outcome = "mostly fine";
    const Check unknown = Evaluate(l, u).checks[0];
    EXPECT_EQ(unknown.outcome, Outcome::kNotEvaluated);
    EXPECT_NE(unknown.note.find("'mostly fine' is not one this version reads"), std::string::npos)
        << unknown.note;
    EXPECT_NE(Summary(Evaluate(l, u))
                  .find("S01: not evaluated: no_unexplained_residual not evaluated "
                        "(the stored analysis outcome 'mostly fine'"),
              std::string::npos)
        << Summary(Evaluate(l, u));
}

TEST(Evaluate, AUnitWithoutCalibrationFailsAndUnjudgeableLimitsAreNotEvaluated) {
    Limits l;
    l.max_residual_rms_over_floor = 3;
    l.max_offset_change_dps = 10;
    l.min_turns = 1;
    UnitEvidence none;
    none.sensor_id = "S09";
    const UnitVerdict v = Evaluate(l, none);
    EXPECT_EQ(v.outcome, Outcome::kFail);
    for (const Check& c : v.checks) EXPECT_EQ(c.outcome, Outcome::kFail) << c.key;
    EXPECT_NE(v.checks[0].note.find("no coefficient set"), std::string::npos);
    // A calibrated unit on exactly as many plateaus as terms: the residual limit is not evaluated,
    // so the unit is not a pass either.
    Limits r;
    r.max_residual_rms_over_floor = 3;
    r.max_offset_change_dps = 10;
    const UnitVerdict w = Evaluate(r, Unit({0, 0, 0}, 0.0));
    EXPECT_EQ(w.checks[0].outcome, Outcome::kNotEvaluated);
    EXPECT_EQ(w.checks[1].outcome, Outcome::kPass);
    EXPECT_EQ(w.outcome, Outcome::kNotEvaluated);
    EXPECT_NE(Summary(w).find("S01: not evaluated: max_residual_rms_over_floor not evaluated"),
              std::string::npos)
        << Summary(w);
}

TEST(Evaluate, HeldOutLimitsJudgeTheFinalSetsAnalysisAndAreNotEvaluatedWithoutOne) {
    // GIVEN limits on the final set's held-out error
    Limits l;
    l.max_heldout_rate_rms_dps = 0.05;
    l.max_heldout_drift_dph = 60;
    // WHEN the closed loop's analysis behind the final set measured 0.03 deg/s and 80 deg/h
    UnitEvidence u = Unit({0, 0, 0, 0, 0}, 0.0);
    u.final_heldout_rate_rms_dps = 0.03;
    u.final_heldout_drift_dph = 80;
    const UnitVerdict v = Evaluate(l, u);
    // THEN the rate passes, the drift fails, each with its measure
    ASSERT_EQ(v.checks.size(), 2u);
    EXPECT_EQ(v.checks[0].key, "max_heldout_rate_rms_dps");
    EXPECT_EQ(v.checks[0].outcome, Outcome::kPass);
    EXPECT_EQ(v.checks[1].outcome, Outcome::kFail);
    EXPECT_NE(Summary(v).find("max_heldout_drift_dph 80 > 60 deg/h"), std::string::npos)
        << Summary(v);
    // AND a final set no analysis made is not evaluated, with the reason (never a silent pass)
    UnitEvidence plain = Unit({0, 0, 0, 0, 0}, 0.0);
    plain.final_heldout_note = "no analysis made the final set";
    const UnitVerdict w = Evaluate(l, plain);
    EXPECT_EQ(w.outcome, Outcome::kNotEvaluated);
    EXPECT_NE(Summary(w).find("no analysis made the final set"), std::string::npos) << Summary(w);
}

TEST(Evaluate, ThePlateauChecksReadThePlateauSetWhenTheFinalSetIsAnother) {
    // GIVEN a final set with a supply term (no plateau ids: fitted on every still bin) and the
    // plateau set beside it, whose plateaus sit 4 sigma off a wrong curve
    UnitEvidence u = Unit({4, -4, 4, -4, 4}, 0.0);
    u.plateau_offset = u.offset;
    u.plateau_sensitivity = u.sensitivity;
    u.offset.term_names.push_back("supply");
    u.offset.coeffs.conservativeResize(4);
    u.offset.coeffs[3] = 0.05;
    u.offset.covariance = Eigen::Matrix4d::Identity() * 1e-12;
    Limits l;
    l.max_residual_rms_over_floor = 3;
    l.max_offset_change_dps = 10;
    const UnitVerdict v = Evaluate(l, u);
    // THEN the residual is the plateau set's (sqrt(5 x 16 / 2) = 6.3 sigma: a fail) and the change
    // the final set's at steady state (nominal supply: the supply term adds nothing): 8.1 deg/s
    EXPECT_NEAR(v.checks[0].measured, std::sqrt(5 * 16.0 / 2), 1e-9);
    EXPECT_EQ(v.checks[0].outcome, Outcome::kFail);
    EXPECT_NEAR(v.checks[1].measured, 0.0405 / 0.005, 1e-3);
    EXPECT_EQ(v.checks[1].outcome, Outcome::kPass);
}

}  // namespace
}  // namespace gyrocal::acceptance
