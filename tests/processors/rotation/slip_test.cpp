// The encoder-slip check (slip_check.hpp) on data from othersim, a rig of another design
// (tests/support/othersim): a turn whose encoder slipped is rejected with the reason, every other
// turn is accepted; and the check on synthetic series.
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include "processors/motion/table_motion.hpp"
#include "processors/rotation/rotation_estimator.hpp"
#include "processors/rotation/slip_check.hpp"
#include "producers/csv/csv_file.hpp"
#include "tests/support/othersim/generator.hpp"

namespace gyrocal::rotation {
namespace {

// The rotation process's wiring on one unit's CSV rows: encoder readings to the move detector
// and the estimator, samples to the estimator.
std::vector<Point> Points(const othersim::Options& o) {
    std::ostringstream text;
    othersim::Generate(o, text);
    std::istringstream in(text.str());
    const csv::CsvFile f = csv::ReadCsv(in, "x.csv", sensor::TempTransfer{}, csv::OnError::kStop);
    motion::MoveDetector detector(motion::MoveDetectorConfig::Defaults());
    RotationEstimator est(RotationConfig::Defaults());
    std::vector<Point> out;
    int64_t seq = 0;
    const int32_t cpr = 20000;  // the CSV importer's --encoder-counts-per-rev default
    for (const csv::CsvRow& r : f.rows) {
        const int64_t utime = csv::TimeUs(r.time_s);
        const motion::EncoderReading e{utime, std::llround(*r.encoder_deg * cpr / 360.0), cpr};
        est.AddEncoder(e);
        if (auto m = detector.Feed(e)) est.AddMove(*m);
        est.AddSample({utime, seq++, r.gyro_v, r.temp_c});
        for (Point& p : est.Poll({detector.watermark_utime(), detector.current_start_utime()}))
            out.push_back(std::move(p));
    }
    return out;
}

othersim::Options Turns() {
    othersim::Options o;
    o.units = 1;
    o.sample_rate_hz = 100;
    o.profile.steps = othersim::ParseSetpoints("25,35,45", 30.0, true);
    o.profile.ramp_c_per_min = 10;
    return o;
}

TEST(EncoderSlip, TheSlippedTurnIsRejectedAndNoOtherOne) {
    othersim::Options o = Turns();
    o.faults.slips.push_back({3, 2.0});  // the second dwell's -90 turn loses 2 deg
    const std::vector<Point> pts = Points(o);
    ASSERT_EQ(pts.size(), 6u);
    for (size_t i = 0; i < pts.size(); ++i) {
        if (i == 3) {
            EXPECT_FALSE(pts[i].accepted);
            EXPECT_NE(pts[i].reject_reason.find("encoder slip"), std::string::npos)
                << pts[i].reject_reason;
        } else {
            EXPECT_TRUE(pts[i].accepted) << i << ": " << pts[i].reject_reason;
        }
    }
}

TEST(EncoderSlip, CleanTurnsOfAnotherRigAreNeverSlips) {
    // 20 seeds x 6 turns of othersim (two-pole output filter, its own encoder resolution):
    // alpha 1e-4 per move, so none of 120 is expected to fail.
    for (uint64_t seed = 1; seed <= 20; ++seed) {
        othersim::Options o = Turns();
        o.seed = seed;
        for (const Point& p : Points(o))
            EXPECT_TRUE(p.accepted) << "seed " << seed << ": " << p.reject_reason;
    }
}

TEST(EncoderSlip, CheckOnSyntheticSeries) {
    // A 3 s move at 30 deg/s of a noiseless gyro (S = 0.006): encoder and gyro agree -> no slip;
    // the encoder loses 1 deg mid-move -> a departure of ~0.5 deg, far above the 0.2 deg floor.
    SlipInputs in;
    in.sensitivity_v_per_dps = 0.006;
    in.count_deg = 0.018;
    double angle = 0;
    for (int k = 0; k <= 300; ++k) {
        const double t = k * 0.01, rate = (t > 0.2 && t < 2.8) ? 30.0 : 0.0;
        in.gyro_t_s.push_back(t);
        in.gyro_rate_v.push_back(0.006 * rate);
        in.encoder_t_s.push_back(t);
        in.encoder_deg.push_back(angle);
        angle += rate * 0.01;
    }
    EXPECT_FALSE(CheckSlip(in, 1e-4, 0.2).slip);
    for (size_t k = 150; k < in.encoder_deg.size(); ++k) in.encoder_deg[k] -= 1.0;
    // the move's own S would absorb part of it; scale the gyro as S = integral / encoder angle
    const double scale = (angle - 1.0) / angle;
    for (double& v : in.gyro_rate_v) v *= scale;
    const SlipResult r = CheckSlip(in, 1e-4, 0.2);
    EXPECT_TRUE(r.slip);
    EXPECT_GT(r.max_deviation_deg, 0.45);
    EXPECT_NEAR(r.at_s, 1.5, 0.05);
}

}  // namespace
}  // namespace gyrocal::rotation
