// Incremental bins (bins_incremental.hpp) against the bins of the raw samples (BinnedRun over
// BuildSensorRun): the same run fed message by message into a RunBinner, in time order, gives the
// same bins and the same analysis.
//
// What must be identical (bit for bit, or to rounding where the sum is reordered): the bins'
// grid, counts, means, segments, table state, chamber air, time since power-on (1e-9 s: a mean
// of differences vs a difference of means), dT/dt for every time constant the analysis names,
// the default branch and heating. The branch of other widths is interpolated between tracked
// widths: within the header's bound (q - 1) / 2 of the branch's full scale, asserted.
// The analysis on both: the same effects added, and the extended models' values on the bins equal
// within a quarter of the noise floor (the analysis' white 10 s-bin scatter): the only difference
// is that interpolation, which can move a searched width by one grid step where the training
// bins' residual is flat in it; a quarter of the floor is far below anything the held-out figures
// resolve (their own sampling error is ~floor / sqrt(held-out bins / 2)).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "processors/analysis/bins_incremental.hpp"
#include "producers/csv/csv_file.hpp"
#include "producers/csv/row_messages.hpp"
#include "tests/processors/analysis/sim_run.hpp"
#include "tests/support/othersim/generator.hpp"

namespace gyrocal::analysis {
namespace {

using testing::MakeSimRun;
using testing::SimRun;
using testing::SimRunOptions;

struct Recorded {
    std::string id = "S01";
    std::vector<GyroSample> gyro;
    std::vector<motion::EncoderReading> encoder;
    std::vector<PowerRecord> power;
    std::vector<AirSample> air;
    std::vector<SensitivityInput> sensitivities;
};

// The raw path: what `gyrocal analyze` builds from the same records.
SensorRun RawRun(const Recorded& r) {
    SensorRun run = BuildSensorRun(r.id, r.gyro, r.encoder, {}, r.sensitivities, r.power);
    AddChamberAir(run, r.air);
    return run;
}

// The incremental path: every message in time order (a reading at the same time as a sample
// after it), as the fitter would receive them; stop at `until_utime` (default: all, then flush).
RunBinner Feed(const Recorded& r, int64_t until_utime = INT64_MAX,
               const IncrementalOptions& options = IncrementalOptions::Defaults()) {
    RunBinner b(options);
    for (const PowerRecord& p : r.power) b.AddPower(r.id, p);
    for (const SensitivityInput& p : r.sensitivities) b.AddSensitivity(r.id, p);
    size_t e = 0, a = 0;
    for (const GyroSample& s : r.gyro) {
        if (s.utime > until_utime) break;
        while (e < r.encoder.size() && r.encoder[e].utime <= s.utime) b.AddEncoder(r.encoder[e++]);
        while (a < r.air.size() && r.air[a].utime <= s.utime) b.AddAir(r.air[a++]);
        b.AddGyro(r.id, s);
    }
    if (until_utime == INT64_MAX) {
        while (e < r.encoder.size()) b.AddEncoder(r.encoder[e++]);
        while (a < r.air.size()) b.AddAir(r.air[a++]);
        b.Flush();
    }
    return b;
}

Recorded FromSim(const SimRun& s) {
    Recorded r;
    r.gyro = s.raw;
    r.encoder = s.encoder;
    r.power = s.power;
    r.air = s.air;
    r.sensitivities = s.run.sensitivities;
    return r;
}

SimRun SimWith(const char* effect, double value, uint64_t seed) {
    SimRunOptions o;
    o.seed = seed;
    o.sensor_tau_s = 15.0;  // the rig's default lag: a temp_rate effect on every ramp
    if (effect) sim::SetEffect(o.effects, effect, value);
    return MakeSimRun(o, true);
}

void ExpectSameBins(const BinnedRun& raw, const BinnedRun& inc) {
    ASSERT_EQ(raw.size(), inc.size());
    // The bins left out below the fill limit, and their samples, are the same too (issue 27).
    EXPECT_EQ(raw.underfilled().bins, inc.underfilled().bins);
    EXPECT_EQ(raw.underfilled().samples, inc.underfilled().samples);
    for (size_t i = 0; i < raw.size(); ++i) {
        const Bin& a = raw.bins()[i];
        const Bin& b = inc.bins()[i];
        ASSERT_EQ(a.start_utime, b.start_utime) << i;
        EXPECT_EQ(a.n, b.n) << i;
        EXPECT_EQ(a.temp_c, b.temp_c) << i;
        EXPECT_EQ(a.gyro_v, b.gyro_v) << i;
        EXPECT_EQ(a.mid_utime, b.mid_utime) << i;
        EXPECT_TRUE(a.supply_v == b.supply_v || (std::isnan(a.supply_v) && std::isnan(b.supply_v)));
        EXPECT_EQ(a.segment, b.segment) << i;
        EXPECT_NEAR(a.time_since_power_s, b.time_since_power_s, 1e-9) << i;
        EXPECT_TRUE(a.air_c == b.air_c || (std::isnan(a.air_c) && std::isnan(b.air_c))) << i;
        EXPECT_EQ(a.table_deg, b.table_deg) << i;
        EXPECT_EQ(a.last_turn_dir, b.last_turn_dir) << i;
    }
}

// Inputs of every tracked time constant are identical; the default branch too; other widths
// within the interpolation bound. Returns the largest branch difference seen.
double ExpectSameInputs(const BinnedRun& raw, const BinnedRun& inc, const TrackerGrid& grid,
                        double width_ratio) {
    int differ = 0;
    for (double tau : grid.rate_taus_s) {
        gyrocal_tracker_config_t c = gyrocal_tracker_config_default();
        c.rate_tau_s = tau;
        for (size_t i = 0; i < raw.size(); ++i) {
            const auto a = raw.Inputs(i, c), b = inc.Inputs(i, c);
            differ += a.dtemp_dt_c_per_s != b.dtemp_dt_c_per_s || a.branch != b.branch ||
                      a.heating != b.heating;
        }
    }
    EXPECT_EQ(differ, 0) << "bins whose dT/dt, default branch or heating differ";
    double worst = 0.0;
    for (double w = 0.25; w <= 8.0; w *= 1.017) {  // between and on the grid's widths
        gyrocal_tracker_config_t c = gyrocal_tracker_config_default();
        c.branch_width_c = w;
        for (size_t i = 0; i < raw.size(); ++i)
            worst = std::max(worst, std::fabs(raw.Inputs(i, c).branch - inc.Inputs(i, c).branch));
    }
    EXPECT_LE(worst, (width_ratio - 1.0) / 2.0) << "the interpolation bound (header)";
    return worst;
}

TEST(IncrementalBins, SameBinsAndInputsAsTheRawSamples) {
    // GIVEN a simulated run with hysteresis (branches), supply, air, power record and turns
    const SimRun s = SimWith("hysteresis", 1e-3, 3);
    const Recorded r = FromSim(s);
    const SensorRun raw_run = RawRun(r);
    // WHEN it is binned from the raw samples and as the messages come
    const RunBinner binner = Feed(r);
    const BinSnapshot snap = binner.Snapshot("S01");
    const BinnedRun raw(raw_run, BinOptions::Defaults());
    const BinnedRun inc = snap.Binned(BinOptions::Defaults());
    // THEN the bins and every exactly tracked input are the same
    ASSERT_GT(raw.size(), 300u);
    ExpectSameBins(raw, inc);
    const IncrementalOptions o = IncrementalOptions::Defaults();
    const double worst = ExpectSameInputs(raw, inc, o.grid, o.width_ratio);
    std::printf(
        "[ incremental ] %zu bins; branch of untracked widths off by at most %.2g (bound %.3g)\n",
        raw.size(), worst, (o.width_ratio - 1.0) / 2.0);
    EXPECT_EQ(snap.run().n_moving_samples, raw_run.n_moving_samples);
    EXPECT_EQ(snap.run().n_bad_samples, raw_run.n_bad_samples);
    EXPECT_EQ(snap.run().n_seq_gaps, raw_run.n_seq_gaps);
    EXPECT_EQ(snap.run().moves.size(), raw_run.moves.size());
    EXPECT_EQ(SamplePeriodS(snap.run()), SamplePeriodS(raw_run));
}

// The analysis on both paths. Returns nothing; asserts the header's tolerances.
void ExpectSameAnalysis(const SensorRun& raw_run, const BinSnapshot& snap, const char* what) {
    const SensorResult a = Analyze(raw_run);
    const SensorResult b = snap.Analyze(AnalysisOptions::Defaults());
    auto effects = [](const SensorResult& r) {
        std::vector<std::string> e;
        for (const AddedEffect& x : r.added) e.push_back(x.effect);
        std::sort(e.begin(), e.end());
        return e;
    };
    std::printf("[ incremental ] %s: raw %s | incremental %s\n", what, a.headline.c_str(),
                b.headline.c_str());
    EXPECT_EQ(effects(a), effects(b)) << what;
    EXPECT_EQ(a.outcome, b.outcome) << what;
    EXPECT_TRUE(snap.Approximations().empty()) << snap.Approximations().front();
    ASSERT_TRUE(a.extended_offset && b.extended_offset) << what;
    const BinnedRun bins(raw_run, BinOptions::Defaults());
    const Eigen::VectorXd d = bins.Values(*a.extended_offset) - bins.Values(*b.extended_offset);
    const double rms = std::sqrt(d.squaredNorm() / static_cast<double>(d.size()));
    std::printf("[ incremental ] %s: models differ by %.3g mV RMS on the bins (floor %.3g mV)\n",
                what, rms * 1e3, a.floor_offset_rms_v * 1e3);
    EXPECT_LT(rms, 0.25 * a.floor_offset_rms_v) << what;
    EXPECT_NEAR(a.error_after.offset_rms_v, b.error_after.offset_rms_v,
                0.05 * a.error_after.offset_rms_v)
        << what;
}

TEST(IncrementalBins, SameAnalysisOnTheRig) {
    for (const auto& [effect, value] : std::vector<std::pair<const char*, double>>{
             {"hysteresis", 1e-3}, {"supply", 0.05}, {"warmup", 2e-3}, {nullptr, 0.0}}) {
        const SimRun s = SimWith(effect, value, 5);
        const Recorded r = FromSim(s);
        ExpectSameAnalysis(RawRun(r), Feed(r).Snapshot("S01"), effect ? effect : "clean");
    }
}

TEST(IncrementalBins, SameAnalysisOnOthersim) {
    // GIVEN othersim (another rig) with a supply effect, through the CSV reader
    othersim::Options o = othersim::Options::QuickReturnToStart(420.0);
    o.units = 1;
    o.seed = 21;
    o.effects.supply_v_per_v = 0.05;
    std::ostringstream text;
    othersim::Generate(o, text);
    std::istringstream in(text.str());
    const csv::CsvFile f =
        csv::ReadCsv(in, "othersim.csv", sensor::TempTransfer{}, csv::OnError::kStop);
    Recorded r;
    r.id = "U1";
    int64_t seq = 0;
    for (const csv::CsvRow& row : f.rows) {
        const int64_t utime = csv::TimeUs(row.time_s);
        r.gyro.push_back({.utime = utime,
                          .seq = seq++,
                          .gyro_v = row.gyro_v,
                          .temp_c = row.temp_c,
                          .supply_v = row.supply_v ? *row.supply_v : kNan});
        r.encoder.push_back({utime, std::llround(*row.encoder_deg * 20000 / 360.0), 20000});
        if (row.chamber_c) r.air.push_back({utime, *row.chamber_c});
    }
    const SensorRun raw_run = RawRun(r);
    const BinSnapshot snap = Feed(r).Snapshot("U1");
    ExpectSameBins(BinnedRun(raw_run, BinOptions::Defaults()), snap.Binned(BinOptions::Defaults()));
    ExpectSameAnalysis(raw_run, snap, "othersim supply");
}

TEST(IncrementalBins, ASnapshotMidRunHasTheDecidedBinsOfTheSamplesSoFar) {
    const SimRun s = SimWith("hysteresis", 1e-3, 4);
    Recorded r = FromSim(s);
    const int64_t cut = r.gyro[r.gyro.size() / 2].utime;
    const RunBinner b = Feed(r, cut);
    Recorded head = r;
    head.gyro.erase(std::remove_if(head.gyro.begin(), head.gyro.end(),
                                   [&](const GyroSample& g) { return g.utime > cut; }),
                    head.gyro.end());
    head.encoder.erase(
        std::remove_if(head.encoder.begin(), head.encoder.end(),
                       [&](const motion::EncoderReading& e) { return e.utime > cut; }),
        head.encoder.end());
    const SensorRun raw_run = RawRun(head);
    const BinnedRun raw(raw_run, BinOptions::Defaults());
    const BinSnapshot snap = b.Snapshot("S01");
    const BinnedRun inc = snap.Binned(BinOptions::Defaults());
    // The last few cells wait for the encoder (a guard past them) or an air reading: a prefix.
    ASSERT_LE(inc.size(), raw.size());
    EXPECT_GE(inc.size() + 8, raw.size());
    for (size_t i = 0; i < inc.size(); ++i) {
        EXPECT_EQ(raw.bins()[i].start_utime, inc.bins()[i].start_utime);
        EXPECT_EQ(raw.bins()[i].gyro_v, inc.bins()[i].gyro_v);
    }
}

TEST(IncrementalBins, BadSamplesAreCountedAsTheRawPathCountsThem) {
    SimRunOptions so;
    so.setpoints_c = {30.0};
    so.dwell_s = 300.0;
    Recorded r = FromSim(MakeSimRun(so, true));
    // A non-finite temperature, a repeated time, one sample lost (a sequence gap).
    r.gyro[100].temp_c = NAN;
    r.gyro[200].utime = r.gyro[199].utime;
    r.gyro.erase(r.gyro.begin() + 300);
    const SensorRun raw_run = RawRun(r);
    const BinSnapshot snap = Feed(r).Snapshot("S01");
    EXPECT_EQ(snap.run().n_bad_samples, 2);
    EXPECT_EQ(snap.run().n_bad_samples, raw_run.n_bad_samples);
    EXPECT_EQ(snap.run().n_seq_gaps, raw_run.n_seq_gaps);
    ExpectSameBins(BinnedRun(raw_run, BinOptions::Defaults()), snap.Binned(BinOptions::Defaults()));
}

TEST(IncrementalBins, BadOptionsAreNamed) {
    IncrementalOptions o = IncrementalOptions::Defaults();
    o.width_ratio = 1.0;
    EXPECT_NE(o.Validate().find("width_ratio"), std::string::npos);
    EXPECT_THROW(RunBinner{o}, std::invalid_argument);
    o = IncrementalOptions::Defaults();
    o.bins.bin_s = 0.0;
    EXPECT_NE(o.Validate().find("bin_s"), std::string::npos);
    EXPECT_THROW(TrackerGrid::For(AnalysisOptions::Defaults(), 3.0), std::invalid_argument);
    const RunBinner b(IncrementalOptions::Defaults());
    EXPECT_THROW(b.Snapshot("nobody"), std::out_of_range);
}

TEST(IncrementalBins, MemoryPerUnitHourIsBoundedByBinsNotSamples) {
    // GIVEN a 100 Hz run of ~1.3 h
    const SimRun s = SimWith(nullptr, 0.0, 6);
    const Recorded r = FromSim(s);
    const RunBinner b = Feed(r);
    const double hours =
        1e-6 * static_cast<double>(r.gyro.back().utime - r.gyro.front().utime) / 3600.0;
    // The ramp fitter before: every sample (and encoder reading) in a vector.
    const double before = static_cast<double>(r.gyro.size() * sizeof(GyroSample) +
                                              r.encoder.size() * sizeof(motion::EncoderReading));
    const double after = static_cast<double>(b.MemoryBytes());
    std::printf(
        "[ incremental ] %.2f h, %zu samples: raw %.2f MB/unit-hour, bins %.3f MB/unit-hour\n",
        hours, r.gyro.size(), before / hours / 1e6, after / hours / 1e6);
    // THEN at least 20x less (the header's ~0.2 MB per unit-hour against ~14 MB)
    EXPECT_LT(after * 20.0, before);
}

// A unit's cells held to max_cells: once more would be closed, neighbours merge into cells twice
// as long, as often as needed. The merged cells are the bins of the doubled length from the start
// (the same samples, the same sums: n, means, time since power-on and every tracked input, to the
// rounding of summing in two parts), but for the chamber air, whose two halves' interpolations are
// weighed (within the air's own change around the bin), and the run's memory stops growing.
TEST(IncrementalBins, CellsHeldToMaxCellsAreTheBinsOfTheDoubledLength) {
    const SimRun s = SimWith("hysteresis", 1e-3, 4);
    const Recorded r = FromSim(s);
    IncrementalOptions capped = IncrementalOptions::Defaults();
    capped.max_cells = 128;
    const RunBinner b = Feed(r, INT64_MAX, capped);
    const BinSnapshot snap = b.Snapshot("S01");
    ASSERT_GT(snap.bin_s(), capped.bins.bin_s) << "the run must be long enough to merge";
    EXPECT_LE(snap.cells(), 128u);
    IncrementalOptions wide = IncrementalOptions::Defaults();
    wide.bins.bin_s = snap.bin_s();
    const RunBinner ref = Feed(r, INT64_MAX, wide);
    BinOptions bo = BinOptions::Defaults();
    bo.bin_s = snap.bin_s();
    const BinnedRun a = ref.Snapshot("S01").Binned(bo), m = snap.Binned(bo);
    ASSERT_GT(a.size(), 20u);
    ASSERT_EQ(a.size(), m.size());
    for (size_t i = 0; i < a.size(); ++i) {
        const Bin& x = a.bins()[i];
        const Bin& y = m.bins()[i];
        ASSERT_EQ(x.start_utime, y.start_utime) << i;
        EXPECT_EQ(x.n, y.n) << i;
        EXPECT_NEAR(x.temp_c, y.temp_c, 1e-9) << i;
        EXPECT_NEAR(x.gyro_v, y.gyro_v, 1e-12) << i;
        EXPECT_NEAR(x.mid_utime, y.mid_utime, 2.0) << i;  // [us] sums of ~1e18 in doubles
        EXPECT_NEAR(x.time_since_power_s, y.time_since_power_s, 1e-9) << i;
        // Both are interpolations of the readings around the bin: they differ by less than the
        // air's own change over it (equal when the air is linear there).
        double lo = 1e9, hi = -1e9;
        for (const AirSample& air : r.air)
            if (air.utime >= x.start_utime - 20'000'000 && air.utime <= x.end_utime + 20'000'000)
                lo = std::min(lo, air.air_c), hi = std::max(hi, air.air_c);
        EXPECT_LE(std::fabs(x.air_c - y.air_c), hi - lo + 1e-9) << i;
        EXPECT_EQ(x.segment, y.segment) << i;
        gyrocal_tracker_config_t c = gyrocal_tracker_config_default();
        EXPECT_NEAR(a.Inputs(i, c).dtemp_dt_c_per_s, m.Inputs(i, c).dtemp_dt_c_per_s, 1e-12) << i;
        EXPECT_NEAR(a.Inputs(i, c).branch, m.Inputs(i, c).branch, 1e-12) << i;
        c.branch_width_c = 2.0;  // a grid width's mean, weighed by the halves' samples (float)
        EXPECT_NEAR(a.Inputs(i, c).branch, m.Inputs(i, c).branch, 1e-5) << i;
    }
    // THEN memory held by the capped binner is below the uncapped one's at 10 s
    const RunBinner full = Feed(r);
    EXPECT_LT(b.MemoryBytes() * 2, full.MemoryBytes());
    IncrementalOptions bad = IncrementalOptions::Defaults();
    bad.max_cells = 10;
    EXPECT_NE(bad.Validate().find("max_cells"), std::string::npos);
}

}  // namespace
}  // namespace gyrocal::analysis
