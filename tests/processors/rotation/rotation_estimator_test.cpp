// RotationEstimator with the shared MoveDetector on synthetic moves with known sensitivity.
#include "processors/rotation/rotation_estimator.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "processors/motion/table_motion.hpp"
#include "tests/processors/rotation/synthetic_rotation.hpp"
#include "tests/processors/validate_check.hpp"

namespace gyrocal::rotation {
namespace {

using testing::Event;
using testing::Move;
using testing::RigSpec;

// Feeds the events through a MoveDetector and one estimator, as gyrocal-rotation does; `drop`
// removes gyro samples (lost packets) by seq.
template <class Drop>
std::vector<Point> Estimate(const std::vector<Event>& events, const RotationConfig& cfg,
                            Drop drop) {
    motion::MoveDetector detector(motion::MoveDetectorConfig::Defaults());
    RotationEstimator est(cfg);
    std::vector<Point> out;
    const RigSpec spec;
    for (const Event& e : events) {
        if (e.is_gyro) {
            if (drop(e.seq)) continue;
            est.AddSample({e.utime, e.seq, e.gyro_v, e.temp_c});
        } else {
            // every reading to the slip check too: these clean moves must never be called slips
            est.AddEncoder({e.utime, e.counts, spec.counts_per_rev});
            if (auto m = detector.Feed({e.utime, e.counts, spec.counts_per_rev})) est.AddMove(*m);
        }
        for (Point& p : est.Poll({detector.watermark_utime(), detector.current_start_utime()}))
            out.push_back(std::move(p));
    }
    return out;
}
std::vector<Point> Estimate(const std::vector<Event>& events, const RotationConfig& cfg) {
    return Estimate(events, cfg, [](int64_t) { return false; });
}

// Expects `p` refused for a reason that says `why`.
void ExpectRefused(const Point& p, const std::string& why) {
    EXPECT_FALSE(p.accepted);
    EXPECT_NE(p.reject_reason.find(why), std::string::npos) << p.reject_reason;
}

TEST(RotationEstimator, RecoversSensitivityInBothDirections) {
    // GIVEN +90, -90, +90, -90 deg moves with a slow offset drift
    RigSpec spec;
    spec.seed = 3;
    const std::vector<Move> moves{{5, 90}, {15, -90}, {25, 90}, {35, -90}};
    const RotationConfig cfg = RotationConfig::Defaults();
    const std::vector<Point> pts = Estimate(testing::Generate(spec, moves, 45), cfg);
    ASSERT_EQ(pts.size(), moves.size());
    // sigma_S from the noise (see ExpectedSensitivityStderr): ~6.6e-6 V/(deg/s), 0.11 %.
    const double sigma_s = testing::ExpectedSensitivityStderr(spec, 90, cfg.guard_s, cfg.rest_s);
    for (size_t i = 0; i < pts.size(); ++i) {
        const Point& p = pts[i];
        SCOPED_TRACE("move " + std::to_string(i));
        ASSERT_TRUE(p.accepted) << p.reject_reason;
        EXPECT_EQ(p.direction, moves[i].angle_deg > 0 ? 1 : -1);
        // THEN S within 4 sigma (trapezoid-rule error at the 4 kinks of the rate profile is
        // <= 4 * 100 deg/s^2 * (0.01 s)^2 / 8 = 5e-3 deg, 5.6e-5 relative: 1/20 of sigma)
        EXPECT_NEAR(p.sensitivity_v_per_dps, spec.sensitivity_v_per_dps, 4 * sigma_s);
        // the encoder angle within one count of the move
        EXPECT_NEAR(p.encoder_angle_deg, moves[i].angle_deg, 360.0 / spec.counts_per_rev + 1e-12);
        // the reported uncertainty agrees with the derived one (batch-means SE with 10 batches
        // scatters ~25 % per window; +-50 % covers it)
        EXPECT_NEAR(p.sensitivity_stderr_v_per_dps / sigma_s, 1.0, 0.5);
        // offset at the window centre: truth within 4 sigma/sqrt(n1 + n2)
        const double t_mid = ((p.start_utime + p.end_utime) / 2 - testing::kT0Utime) * 1e-6;
        EXPECT_NEAR(p.offset_v, spec.offset_v + spec.drift_v_per_s * t_mid,
                    4 * spec.noise_v / std::sqrt(400.0));
        EXPECT_NEAR(p.temp_c, spec.temp_c, 4 * 0.05 / std::sqrt(static_cast<double>(p.n_samples)));
        EXPECT_EQ(p.rotation_id, p.start_utime);
        EXPECT_EQ(p.last_seq - p.first_seq + 1, p.n_samples);
        EXPECT_NEAR(p.integral_v_s, p.sensitivity_v_per_dps * p.encoder_angle_deg, 1e-12);
    }
}

TEST(RotationEstimator, ALinearOffsetDriftIsRemoved) {
    // GIVEN a fast drift of 1 mV/s: over the ~4.3 s integration window it moves the offset by
    // 4.3 mV; taking the offset from the rest window before the move alone would bias S by
    // drift * T_int^2 / 2 / 90 deg ~ 1e-4 V/(deg/s), 15 sigma.
    RigSpec spec;
    spec.drift_v_per_s = 1e-3;
    spec.seed = 8;
    const RotationConfig cfg = RotationConfig::Defaults();
    const double sigma_s = testing::ExpectedSensitivityStderr(spec, 90, cfg.guard_s, cfg.rest_s);
    const double t_int = testing::MoveDuration(spec, 90) + 2 * cfg.guard_s;
    ASSERT_GT(spec.drift_v_per_s * t_int * t_int / 2 / 90, 10 * sigma_s);  // the test can fail
    const std::vector<Point> pts = Estimate(testing::Generate(spec, {{5, 90}, {15, -90}}, 25), cfg);
    ASSERT_EQ(pts.size(), 2u);
    for (const Point& p : pts) {
        ASSERT_TRUE(p.accepted) << p.reject_reason;
        EXPECT_NEAR(p.sensitivity_v_per_dps, spec.sensitivity_v_per_dps, 4 * sigma_s);
    }
}

// rms of z = (S - S_true) / reported stderr over 60 seeds x 2 moves.
double RmsZ(double noise_rho) {
    const RotationConfig cfg = RotationConfig::Defaults();
    double sum_z2 = 0;
    int n = 0;
    for (uint64_t seed = 100; seed < 160; ++seed) {
        RigSpec spec;
        spec.seed = seed;
        spec.noise_rho = noise_rho;
        for (const Point& p : Estimate(testing::Generate(spec, {{5, 90}, {15, -90}}, 25), cfg)) {
            EXPECT_TRUE(p.accepted) << p.reject_reason;
            const double z = (p.sensitivity_v_per_dps - spec.sensitivity_v_per_dps) /
                             p.sensitivity_stderr_v_per_dps;
            sum_z2 += z * z;
            ++n;
        }
    }
    EXPECT_EQ(n, 120);
    return std::sqrt(sum_z2 / n);
}

TEST(RotationEstimator, ReportedUncertaintyMatchesTheScatterOverSeeds) {
    // THEN rms(z) ~ 1: its sampling sd is 1/sqrt(2n) = 0.065, and the scatter of each reported
    // stderr (batch means, 10 batches per rest window) inflates it by a few %: accept
    // [0.8, 1.25] (3 sd + that bias). White noise, and AR(1) noise with rho = 0.8 (a heavy LPF:
    // the integral's noise is then 3x the white formula, sqrt((1 + rho)/(1 - rho))), which the
    // batch-means noise level must catch.
    for (double rho : {0.0, 0.8}) {
        SCOPED_TRACE(rho);
        const double rms = RmsZ(rho);
        EXPECT_GT(rms, 0.8);
        EXPECT_LT(rms, 1.25);
    }
}

TEST(RotationEstimator, RejectsNonFiniteInput) {
    // The process guards drop NaN samples (which then show as a sequence gap); the library
    // itself still refuses a non-finite result rather than publishing it.
    RigSpec spec;
    std::vector<Event> ev = testing::Generate(spec, {{5, 90}}, 12);
    for (Event& e : ev) {
        if (e.is_gyro && e.seq == 600) e.gyro_v = std::nan("");
    }
    const std::vector<Point> pts = Estimate(ev, RotationConfig::Defaults());
    ASSERT_EQ(pts.size(), 1u);
    ExpectRefused(pts[0], "not finite");
}

TEST(RotationEstimator, RejectsAMoveWithASequenceGapInside) {
    RigSpec spec;
    const std::vector<Event> ev = testing::Generate(spec, {{5, 90}, {15, -90}}, 25);
    // Lose 3 samples in the middle of the first move (t = 6.5 s) and 1 in the rest window
    // before the second (t = 12.6 s).
    const std::vector<Point> pts = Estimate(ev, RotationConfig::Defaults(), [](int64_t seq) {
        return (seq >= 650 && seq < 653) || seq == 1260;
    });
    ASSERT_EQ(pts.size(), 2u);
    ExpectRefused(pts[0], "3 samples missing (sequence gaps)");
    ExpectRefused(pts[1], "1 samples missing");
}

TEST(RotationEstimator, RejectsATinyMove) {
    RigSpec spec;
    const std::vector<Point> pts =
        Estimate(testing::Generate(spec, {{5, 2.0}}, 12), RotationConfig::Defaults());
    ASSERT_EQ(pts.size(), 1u);
    ExpectRefused(pts[0], "below the minimum angle");
    EXPECT_NEAR(pts[0].encoder_angle_deg, 2.0, 360.0 / spec.counts_per_rev + 1e-12);
}

TEST(RotationEstimator, RejectsMovesWithoutEnoughRestBetweenThem) {
    // GIVEN a second move 1 s after the first ends: neither the rest after the first nor the
    // rest before the second can hold 0.8 x 2 s outside the 0.5 s guards.
    RigSpec spec;
    const double end1 = 5 + testing::MoveDuration(spec, 90);
    const std::vector<Point> pts =
        Estimate(testing::Generate(spec, {{5, 90}, {end1 + 1.0, -90}}, end1 + 10),
                 RotationConfig::Defaults());
    ASSERT_EQ(pts.size(), 2u);
    ExpectRefused(pts[0], "rest window after");
    ExpectRefused(pts[1], "rest window before");
}

TEST(RotationEstimator, WaitsForTheRestWindowAfterTheMove) {
    // The point comes only once the rest after the move (guard + rest = 2.5 s) has been seen.
    RigSpec spec;
    const std::vector<Event> ev = testing::Generate(spec, {{5, 90}}, 20);
    motion::MoveDetector detector(motion::MoveDetectorConfig::Defaults());
    RotationEstimator est(RotationConfig::Defaults());
    int64_t emitted_at = 0;
    for (const Event& e : ev) {
        if (e.is_gyro)
            est.AddSample({e.utime, e.seq, e.gyro_v, e.temp_c});
        else if (auto m = detector.Feed({e.utime, e.counts, spec.counts_per_rev}))
            est.AddMove(*m);
        if (!est.Poll({detector.watermark_utime(), detector.current_start_utime()}).empty()) {
            emitted_at = e.utime;
            break;
        }
    }
    const double t = (emitted_at - testing::kT0Utime) * 1e-6;
    const double end = 5 + testing::MoveDuration(spec, 90);
    EXPECT_GE(t, end + 0.5 + 2.0);
    EXPECT_LE(t, end + 0.5 + 2.0 + 0.5 + 0.05);  // + the encoder's guard past the window
}

TEST(RotationConfig, ValidateNamesTheField) {
    const RotationConfig c = gyrocal::testing::ExpectRefusedNaming(
        RotationConfig{}, [](auto& o) { o.rest_s = 0; }, "rest_s");
    EXPECT_THROW(RotationEstimator{c}, std::invalid_argument);
}

}  // namespace
}  // namespace gyrocal::rotation
