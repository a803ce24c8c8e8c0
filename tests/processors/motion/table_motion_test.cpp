// Turntable move detection and sample classification from encoder readings.
#include "processors/motion/table_motion.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "tests/processors/validate_check.hpp"

namespace gyrocal::motion {
namespace {

constexpr int32_t kCpr = 144000;  // 36000 lines x 4
constexpr int64_t kT0 = 1'000'000'000'000'000;

// Angle of a trapezoid move of `angle_deg` starting at t_start: accel 100 deg/s^2, cruise 30 deg/s.
double TrapezoidAngle(double t, double t_start, double angle_deg) {
    const double acc = 100, v = 30, sgn = angle_deg >= 0 ? 1 : -1, a = std::fabs(angle_deg);
    const double ta = v / acc, da = 0.5 * acc * ta * ta, tc = (a - 2 * da) / v;
    double x = t - t_start;
    if (x <= 0) return 0;
    if (x < ta) return sgn * 0.5 * acc * x * x;
    if (x < ta + tc) return sgn * (da + v * (x - ta));
    if (x < 2 * ta + tc) {
        const double r = 2 * ta + tc - x;
        return sgn * (a - 0.5 * acc * r * r);
    }
    return sgn * a;
}

int64_t Counts(double deg) { return static_cast<int64_t>(std::floor(deg / 360.0 * kCpr)); }

TEST(MoveDetector, FindsATrapezoidMoveAndItsExactAngle) {
    MoveDetector det(MoveDetectorConfig::Defaults());
    std::vector<TableMove> moves;
    // 1 kHz encoder: rest with 1-count dither, +90 deg at t = 5 s (3.3 s long), rest again.
    for (int k = 0; k < 15000; ++k) {
        const double t = k * 1e-3;
        const int64_t dither = (k / 37) % 2;
        const EncoderReading r{kT0 + k * 1000, 1000 + Counts(TrapezoidAngle(t, 5.0, 90.0)) + dither,
                               kCpr};
        if (auto m = det.Feed(r)) moves.push_back(*m);
    }
    ASSERT_EQ(moves.size(), 1u);
    const TableMove& m = moves[0];
    // The angle is the count difference of the rest positions (dither allowed: +-1 count).
    EXPECT_NEAR(m.angle_deg(), 90.0, 1.0 * 360.0 / kCpr + 1e-12);
    // Start: last rest reading before > 2 counts: 2 counts = 0.005 deg, reached at
    // sqrt(2*0.005/100) = 10 ms into the accel; end at the last change, 3.3 s later.
    const double start_s = (m.start_utime - kT0) * 1e-6, end_s = (m.end_utime - kT0) * 1e-6;
    EXPECT_GE(start_s, 5.0 - 0.001);
    EXPECT_LE(start_s, 5.0 + 0.012);
    EXPECT_NEAR(end_s, 5.0 + 3.3, 0.05);
    EXPECT_FALSE(det.moving());
}

TEST(MoveDetector, TheLastCountsOfASlowApproachAreInTheAngle) {
    // GIVEN a move to 2500 counts whose last 3 counts come one at a time, 0.15 s apart (inside
    // the 1-count settle band, each): the angle must be the final position, exactly.
    MoveDetector det(MoveDetectorConfig::Defaults());
    std::vector<TableMove> moves;
    for (int k = 0; k < 5000; ++k) {
        const double t = k * 1e-2;  // 100 Hz
        int64_t c = 0;
        if (t >= 10 && t < 11)
            c = static_cast<int64_t>((t - 10) * 2497);
        else if (t >= 11)
            c = 2497 + std::min<int64_t>(3, static_cast<int64_t>((t - 11) / 0.15));
        if (auto m = det.Feed({kT0 + k * 10'000, c, 10000})) moves.push_back(*m);
    }
    ASSERT_EQ(moves.size(), 1u);
    EXPECT_EQ(moves[0].end_counts - moves[0].start_counts, 2500);
}

TEST(MoveDetector, DitherAtRestIsNotAMove) {
    MoveDetector det(MoveDetectorConfig::Defaults());
    for (int k = 0; k < 5000; ++k) {
        const EncoderReading r{kT0 + k * 1000, 500 + (k % 3 == 0 ? 1 : 0) - (k % 7 == 0 ? 1 : 0),
                               kCpr};
        EXPECT_FALSE(det.Feed(r).has_value());
        EXPECT_FALSE(det.moving());
    }
}

TEST(TableMotion, ClassifiesSamplesWithinTheGuardAndWaitsForTheEncoder) {
    const double guard_s = 1.0, stale_s = 2.0;
    TableMotion motion(MoveDetectorConfig::Defaults(), guard_s, stale_s);
    auto at = [](double s) { return kT0 + static_cast<int64_t>(std::llround(s * 1e6)); };
    for (int k = 0; k <= 12000; ++k) {
        const double t = k * 1e-3;
        motion.Feed({at(t), Counts(TrapezoidAngle(t, 5.0, -90.0)), kCpr});
    }
    // Encoder heard up to 12 s: samples up to 11 s are decided, later ones wait
    EXPECT_TRUE(motion.Decided(at(11.0), at(11.0)));
    EXPECT_FALSE(motion.Decided(at(11.5), at(11.5)));
    // ... unless their own stream is stale_s + guard ahead (encoder silent)
    EXPECT_TRUE(motion.Decided(at(11.5), at(11.5 + guard_s + stale_s)));
    // Move 5.0 .. 8.3 s, guard 1 s: moving in [4.0, 9.3]
    EXPECT_FALSE(motion.Moving(at(3.9)));
    EXPECT_TRUE(motion.Moving(at(4.05)));
    EXPECT_TRUE(motion.Moving(at(6.0)));
    EXPECT_TRUE(motion.Moving(at(9.2)));
    EXPECT_FALSE(motion.Moving(at(9.4)));
}

TEST(TableMotion, AMoveUnderWayMarksEverythingAfterItsStart) {
    TableMotion motion(MoveDetectorConfig::Defaults(), 0.5, 2.0);
    for (int k = 0; k <= 6000; ++k) {  // move starts at 5 s, still turning at 6 s
        const double t = k * 1e-3;
        motion.Feed({kT0 + k * 1000, Counts(TrapezoidAngle(t, 5.0, 90.0)), kCpr});
    }
    EXPECT_TRUE(motion.detector().moving());
    EXPECT_TRUE(motion.Moving(kT0 + 4'600'000));
    EXPECT_TRUE(motion.Moving(kT0 + 60'000'000));
    EXPECT_FALSE(motion.Moving(kT0 + 4'400'000));
}

TEST(MoveDetectorConfig, ValidateNamesTheField) {
    testing::ExpectRefusedNaming(
        MoveDetectorConfig{}, [](auto& c) { c.settle_s = 0; }, "settle_s");
    testing::ExpectRefusedNaming(
        MoveDetectorConfig{}, [](auto& c) { c.start_threshold_counts = 0; },
        "start_threshold_counts");
}

}  // namespace
}  // namespace gyrocal::motion
