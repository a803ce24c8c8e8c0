// What the analysis leaves out is counted and said in its notes (issue 27): encoder readings it
// cannot use, bins below the fill limit, and, when the encoder failed (motion unknown), the bins
// outside the plateau windows; the same counts on the raw and the incremental path. The inputs
// are exact, so are the counts.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "processors/analysis/analyze.hpp"
#include "processors/analysis/bins.hpp"
#include "processors/analysis/bins_incremental.hpp"
#include "processors/analysis/run_data.hpp"

namespace gyrocal::analysis {
namespace {

bool Mentions(const std::vector<std::string>& notes, const std::string& what) {
    return std::any_of(notes.begin(), notes.end(),
                       [&](const std::string& n) { return n.find(what) != std::string::npos; });
}

// What binning `what` kept, `kept` bins, and left out and counted: the bins and samples below the
// fill limit and those outside the plateau windows of a run whose motion is unknown.
void ExpectBinned(const char* what, const BinnedRun& b, size_t kept, BinDrops underfilled,
                  BinDrops unknown_motion) {
    SCOPED_TRACE(what);
    EXPECT_EQ(b.size(), kept);
    EXPECT_EQ(b.underfilled().bins, underfilled.bins);
    EXPECT_EQ(b.underfilled().samples, underfilled.samples);
    EXPECT_EQ(b.unknown_motion().bins, unknown_motion.bins);
    EXPECT_EQ(b.unknown_motion().samples, unknown_motion.samples);
}

// 100 Hz samples at rest from 0 to n / 100 s, but the ones in [skip_from, skip_to).
std::vector<GyroSample> Samples(int n, int skip_from = 0, int skip_to = 0) {
    std::vector<GyroSample> raw;
    for (int i = 0; i < n; ++i)
        if (i < skip_from || i >= skip_to)
            raw.push_back(
                {.utime = i * 10'000, .seq = i, .gyro_v = 2.5, .temp_c = 25.0, .supply_v = kNan});
    return raw;
}

// An encoder at rest, 100 Hz for 400 s, 20000 counts/rev.
std::vector<motion::EncoderReading> RestingEncoder() {
    std::vector<motion::EncoderReading> enc;
    for (int i = 0; i < 40000; ++i) enc.push_back({i * 10'000, 5000, 20000});
    return enc;
}

PlateauInput Window(double start_s, double end_s) {
    PlateauInput p;
    p.start_utime = static_cast<int64_t>(start_s * 1e6);
    p.end_utime = static_cast<int64_t>(end_s * 1e6);
    return p;
}

TEST(Drops, EncoderReadingsNotAfterThePreviousOrWithoutCprAreCounted) {
    // GIVEN 40000 good readings, 7 repeating a time already read and 5 without counts_per_rev
    std::vector<motion::EncoderReading> enc = RestingEncoder();
    for (int k = 0; k < 7; ++k) enc.push_back({k * 1'000'000, 5001, 20000});
    for (int k = 0; k < 5; ++k) enc.push_back({k * 1'000'000 + 5'000, 5000, 0});
    // THEN 12 are dropped and counted, on the raw path and on the incremental one
    int64_t bad = -1;
    MovesFromEncoder(enc, BuildOptions::Defaults(), &bad);
    EXPECT_EQ(bad, 12);
    std::vector<motion::EncoderReading> in_time = enc;
    std::stable_sort(in_time.begin(), in_time.end(),
                     [](const motion::EncoderReading& a, const motion::EncoderReading& b) {
                         return a.utime < b.utime;
                     });
    RunMotion motion(BuildOptions::Defaults());
    for (const motion::EncoderReading& e : in_time) motion.Add(e);
    EXPECT_EQ(motion.bad_readings(), 12);
    EXPECT_FALSE(motion.motion_unknown());
    const SensorRun run = BuildSensorRun("S01", Samples(40000), enc, {}, {});
    EXPECT_EQ(run.n_bad_encoder, 12);
    EXPECT_FALSE(run.motion_unknown);
    EXPECT_EQ(run.n_moving_samples, 0);  // the dropped readings made no move
    // AND the analysis notes say it
    const SensorResult r = Analyze(run);
    EXPECT_TRUE(Mentions(r.notes, "12 encoder readings with a time not after the previous"));
    EXPECT_FALSE(Mentions(r.notes, "table motion unknown"));
}

TEST(Drops, BinsBelowTheFillLimitAreCountedWithTheirSamples) {
    // GIVEN 405 s at 100 Hz with 3 s (300 samples) missing in the bin [100 s, 110 s): that bin
    // holds 700 and the run's last bin [400 s, 405 s) 500, both below 0.8 x 1000
    const SensorRun run = BuildSensorRun("S01", Samples(40500, 10000, 10300), {}, {}, {});
    const BinnedRun binned(run, BinOptions::Defaults());
    // THEN 2 bins holding 1200 samples are left out and counted, 39 kept
    ExpectBinned("batch", binned, 39, {.bins = 2, .samples = 1200}, {});
    const SensorResult r = AnalyzeBinned(run, binned);
    EXPECT_TRUE(Mentions(r.notes, "2 bins at rest below the fill limit"));
    EXPECT_TRUE(Mentions(r.notes, "holding 1200 samples"));
    // AND the incremental bins count the same
    RunBinner b(IncrementalOptions::Defaults());
    for (const GyroSample& s : Samples(40500, 10000, 10300)) b.AddGyro("S01", s);
    b.Flush();
    const BinSnapshot snap = b.Snapshot("S01");
    ExpectBinned("incremental", snap.Binned(BinOptions::Defaults()), 39,
                 {.bins = 2, .samples = 1200}, {});
    EXPECT_TRUE(Mentions(snap.Analyze(AnalysisOptions::Defaults()).notes, "holding 1200 samples"));
}

TEST(Drops, AFailedEncoderMakesMotionUnknownAndKeepsOnlyPlateauWindows) {
    // GIVEN 400 s at 100 Hz, plateau windows [100 s, 150 s] and [300 s, 360 s], and an encoder
    // whose every reading lacks counts_per_rev
    std::vector<motion::EncoderReading> enc = RestingEncoder();
    for (motion::EncoderReading& e : enc) e.counts_per_rev = 0;
    const std::vector<PlateauInput> windows = {Window(100, 150), Window(300, 360)};
    const SensorRun run = BuildSensorRun("S01", Samples(40000), enc, windows, {});
    // THEN motion is unknown, every reading is counted, and only the 5 + 6 bins inside the
    // windows are kept: 29 bins of 1000 samples are left out and counted
    EXPECT_TRUE(run.motion_unknown);
    EXPECT_EQ(run.n_bad_encoder, 40000);
    const BinnedRun binned(run, BinOptions::Defaults());
    ExpectBinned("batch", binned, 11, {}, {.bins = 29, .samples = 29000});
    const SensorResult r = AnalyzeBinned(run, binned);
    EXPECT_TRUE(Mentions(r.notes, "table motion unknown"));
    EXPECT_TRUE(Mentions(r.notes, "29 bins holding 29000 samples outside them left out"));
    EXPECT_TRUE(Mentions(r.notes, "40000 encoder readings with a time not after the previous"));
    // AND the incremental path does the same
    RunBinner b(IncrementalOptions::Defaults());
    for (const motion::EncoderReading& e : enc) b.AddEncoder(e);
    for (const GyroSample& s : Samples(40000)) b.AddGyro("S01", s);
    for (const PlateauInput& p : windows) b.AddPlateau("S01", p);
    b.Flush();
    const BinSnapshot snap = b.Snapshot("S01");
    EXPECT_TRUE(snap.run().motion_unknown);
    EXPECT_EQ(snap.run().n_bad_encoder, 40000);
    ExpectBinned("incremental", snap.Binned(BinOptions::Defaults()), 11, {},
                 {.bins = 29, .samples = 29000});
}

TEST(Drops, NoEncoderWithRotationsSaysTheTurnsAreInTheStillData) {
    // GIVEN a run without encoder readings whose rotation estimator published 2 points
    std::vector<SensitivityInput> points(2);
    const SensorRun run = BuildSensorRun("S01", Samples(40000), {}, {}, points);
    // THEN every sample counts as still (a run recorded without an encoder) and the note says
    // the run's 2 rotations are in the still data
    EXPECT_FALSE(run.motion_unknown);
    EXPECT_EQ(run.n_still(), 40000);
    const SensorResult r = Analyze(run);
    EXPECT_TRUE(
        Mentions(r.notes, "the run recorded 2 rotations: their turns are in the still data"));
}

}  // namespace
}  // namespace gyrocal::analysis
