// RecordMapper without sockets: encoded messages in, rows out.
#include "store/recorder/record_mapper.hpp"

#include <gtest/gtest.h>

#include "gyrocal/analysis_t.hpp"
#include "gyrocal/fit_report_t.hpp"
#include "gyrocal/noise_t.hpp"
#include "store/recorder/message_fields.hpp"
#include "tests/lcmtypes/message_builders.hpp"

namespace gyrocal::recorder {
namespace {

using namespace gyrocal::testing;

template <class Msg>
Mapped MapMsg(RecordMapper& m, const std::string& channel, const Msg& msg, int64_t recv = 7) {
    const auto bytes = EncodeMsg(msg);
    return m.Map(channel, bytes.data(), static_cast<int>(bytes.size()), recv);
}

TEST(RecordMapper, GyroSampleKeepsEveryFieldAndTheRunInForce) {
    RecordMapper m(MapperOptions::Defaults(), "");
    gyro_sample_t g = Gyro("S01", 5);
    g.has_adc = true;
    g.gyro_counts = 1234;
    Mapped out = MapMsg(m, "GYRO_S01", g, 99);
    ASSERT_TRUE(out.row);
    const auto& r = std::get<db::GyroRow>(*out.row);
    EXPECT_EQ(r.run_id, "");
    EXPECT_EQ(r.sensor_id, "S01");
    EXPECT_EQ(r.seq, 5);
    EXPECT_EQ(r.utime, g.utime);
    EXPECT_DOUBLE_EQ(r.gyro_v, g.gyro_v);
    EXPECT_DOUBLE_EQ(r.temp_c, g.temp_c);
    EXPECT_TRUE(std::isnan(r.supply_v));
    EXPECT_EQ(r.gyro_counts, 1234);
    EXPECT_EQ(r.recv_utime, 99);
    EXPECT_FALSE(out.essential);
}

TEST(RecordMapper, RunEventsDecideTheRunOfLaterMessages) {
    RecordMapper m(MapperOptions::Defaults(), "");
    Mapped start = MapMsg(m, "RUN_EVENT", RunEvent("R1", "start", {"S01"}));
    EXPECT_TRUE(start.essential);
    EXPECT_EQ(std::get<db::RunEventRow>(*start.row).run_id, "R1");
    EXPECT_EQ(m.current_run(), "R1");
    EXPECT_EQ(std::get<db::GyroRow>(*MapMsg(m, "GYRO_S01", Gyro("S01", 0)).row).run_id, "R1");
    // A plateau keeps the run it carries, even when another is in force.
    EXPECT_EQ(
        std::get<db::PlateauRow>(*MapMsg(m, "PLATEAU_S01", Plateau("S01", "R0", 0, 9)).row).run_id,
        "R0");
    Mapped stop = MapMsg(m, "RUN_EVENT", RunEvent("R1", "stop", {"S01"}));
    EXPECT_EQ(std::get<db::RunEventRow>(*stop.row).run_id, "R1");
    EXPECT_EQ(m.current_run(), "");
    EXPECT_EQ(std::get<db::GyroRow>(*MapMsg(m, "GYRO_S01", Gyro("S01", 1)).row).run_id, "");
}

TEST(RecordMapper, RestartedRecorderContinuesTheOpenRun) {
    RecordMapper m(MapperOptions::Defaults(), "R7");
    EXPECT_EQ(std::get<db::EncoderRow>(*MapMsg(m, "ENCODER", Encoder(0)).row).run_id, "R7");
}

TEST(RecordMapper, UnknownFingerprintBecomesARawEventWithItsBytes) {
    RecordMapper m(MapperOptions::Defaults(), "R1");
    const std::vector<uint8_t> bytes = {0xde, 0xad, 0xbe, 0xef, 0, 1, 2, 3, 42, 43};
    Mapped out = m.Map("MYSTERY", bytes.data(), static_cast<int>(bytes.size()), 5);
    const auto& r = std::get<db::RawEventRow>(*out.row);
    EXPECT_EQ(r.channel, "MYSTERY");
    EXPECT_EQ(r.reason, "unknown_type");
    EXPECT_EQ(r.fingerprint_hex, "deadbeef00010203");
    EXPECT_EQ(r.data, bytes);
    EXPECT_EQ(r.run_id, "R1");
    EXPECT_EQ(out.loss.decode_errors, 0);
}

TEST(RecordMapper, ShortMessageIsARawEventNotACrash) {
    RecordMapper m(MapperOptions::Defaults(), "");
    const uint8_t b[3] = {1, 2, 3};
    Mapped out = m.Map("X", b, 3, 5);
    EXPECT_EQ(std::get<db::RawEventRow>(*out.row).fingerprint_hex, "");
    Mapped empty = m.Map("X", nullptr, 0, 5);
    EXPECT_TRUE(std::get<db::RawEventRow>(*empty.row).data.empty());
}

TEST(RecordMapper, KnownFingerprintThatDoesNotDecodeCountsADecodeError) {
    RecordMapper m(MapperOptions::Defaults(), "R1");
    auto bytes = EncodeMsg(Gyro("S01", 1));
    bytes.resize(bytes.size() - 5);  // truncated: the hash matches, the body does not
    Mapped out = m.Map("GYRO_S01", bytes.data(), static_cast<int>(bytes.size()), 5);
    EXPECT_EQ(std::get<db::RawEventRow>(*out.row).reason, "decode_error");
    EXPECT_EQ(out.loss.decode_errors, 1);
    EXPECT_EQ(out.run_id, "R1");
}

// Found by the fuzz harness recorder_map: the mapper called the generated decode directly, so a
// negative array length escaped as std::length_error and ended gyrocal-recorder. Now it is a
// decode error like any other, kept whole as a raw event.
TEST(RecordMapper, AHostileArrayLengthIsADecodeErrorNotAnException) {
    RecordMapper m(MapperOptions::Defaults(), "R1");
    auto bytes = EncodeMsg(RunEvent("R2", "start", {"S01"}));
    // After hash, utime, run_id "R2", event "start", reason "", setpoint_index, setpoint_c:
    // num_sensors (int16, big-endian) made negative.
    const size_t at = 8 + 8 + (4 + 3) + (4 + 6) + (4 + 1) + 4 + 8;
    bytes[at] = 0x80;
    Mapped out;
    ASSERT_NO_THROW(out = m.Map("RUN_EVENT", bytes.data(), static_cast<int>(bytes.size()), 5));
    EXPECT_EQ(std::get<db::RawEventRow>(*out.row).reason, "decode_error");
    EXPECT_EQ(out.loss.decode_errors, 1);
    EXPECT_EQ(m.current_run(), "R1");  // an event that did not decode changes nothing
}

TEST(RecordMapper, TypeComesFromTheFingerprintNotTheChannel) {
    RecordMapper m(MapperOptions::Defaults(), "");
    Mapped out = MapMsg(m, "GYRO_S01", Encoder(3));  // an encoder sample on a gyro channel
    EXPECT_TRUE(std::holds_alternative<db::EncoderRow>(*out.row));
}

TEST(RecordMapper, SequenceGapsAreCountedPerChannel) {
    RecordMapper m(MapperOptions::Defaults(), "R1");
    EXPECT_EQ(MapMsg(m, "GYRO_S01", Gyro("S01", 0)).loss.seq_gaps, 0);
    EXPECT_EQ(MapMsg(m, "GYRO_S02", Gyro("S02", 0)).loss.seq_gaps, 0);
    EXPECT_EQ(MapMsg(m, "GYRO_S01", Gyro("S01", 4)).loss.seq_gaps, 3);
    EXPECT_EQ(MapMsg(m, "GYRO_S02", Gyro("S02", 1)).loss.seq_gaps, 0);
    Mapped back = MapMsg(m, "GYRO_S01", Gyro("S01", 2));
    EXPECT_EQ(back.loss.seq_backwards, 1);
}

TEST(RecordMapper, RatesCanBeSkippedButStillCountGaps) {
    RecordMapper m(MapperOptions{false}, "");
    EXPECT_FALSE(MapMsg(m, "RATE_S01", Rate("S01", 0)).row);
    Mapped out = MapMsg(m, "RATE_S01", Rate("S01", 3));
    EXPECT_FALSE(out.row);
    EXPECT_EQ(out.loss.seq_gaps, 2);
}

TEST(RecordMapper, EveryKnownTypeMapsToItsRow) {
    RecordMapper m(MapperOptions::Defaults(), "R1");
    EXPECT_TRUE(
        std::holds_alternative<db::ChamberStateRow>(*MapMsg(m, "CHAMBER_STATE", Chamber(0)).row));
    EXPECT_TRUE(
        std::holds_alternative<db::ChamberCmdRow>(*MapMsg(m, "CHAMBER_CMD", ChamberCmd("R1")).row));
    EXPECT_TRUE(std::holds_alternative<db::TurntableCmdRow>(
        *MapMsg(m, "TURNTABLE_CMD", TurntableCmd("R1")).row));
    EXPECT_TRUE(std::holds_alternative<db::PlateauStateRow>(
        *MapMsg(m, "STABILITY_S01", PlateauState("S01")).row));
    EXPECT_TRUE(std::holds_alternative<db::SensitivityRow>(
        *MapMsg(m, "SENSITIVITY_S01", Sensitivity("S01", "R1", 0, 9)).row));
    EXPECT_TRUE(std::holds_alternative<db::RateRow>(*MapMsg(m, "RATE_S01", Rate("S01", 0)).row));
    const auto st = std::get<db::StatusRow>(*MapMsg(m, "STATUS", Status("p")).row);
    EXPECT_EQ(st.extra_json, R"({"x":1.5})");
    Mapped c = MapMsg(m, "COEFFS_S01", Coeffs("S01", "R1", 5, {1, 2}, {3}));
    EXPECT_TRUE(c.essential);
    const auto& cs = std::get<db::CoeffSetRow>(*c.row);
    EXPECT_EQ(cs.plateau_ids, (std::vector<int64_t>{1, 2}));
    EXPECT_EQ(cs.rotation_ids, (std::vector<int64_t>{3}));
    EXPECT_EQ(cs.offset.term_names.size(), 3u);
    EXPECT_EQ(cs.sensitivity.covariance.size(), 2u);
}

}  // namespace
}  // namespace gyrocal::recorder

namespace gyrocal::recorder {
namespace {

using namespace gyrocal::testing;

template <class Msg>
Mapped MapV5(RecordMapper& m, const std::string& channel, const Msg& msg) {
    const auto bytes = EncodeMsg(msg);
    return m.Map(channel, bytes.data(), static_cast<int>(bytes.size()), 5);
}

// NOISE_<id> and FIT_<id> keep the run they carry and are never dropped by the queue.
// The key a verdict names its set by (message_fields.hpp), shared by analyses and fit reports:
// all six fields across, both ways, and nothing else.
TEST(RecordMapper, VerdictKeyIsTheSetsKeyWithTimeAndFinality) {
    const auto expect_key = [](const auto& to) {
        EXPECT_EQ(to.utime, 11);
        EXPECT_EQ(to.sensor_id, "U1");
        EXPECT_EQ(to.run_id, "R1");
        EXPECT_EQ(to.coeff_set_id, 42);
        EXPECT_EQ(to.source, "fitter");
        EXPECT_TRUE(to.is_final);
    };
    fit_report_t f{};
    f.utime = 11, f.sensor_id = "U1", f.run_id = "R1", f.coeff_set_id = 42;
    f.source = "fitter", f.is_final = true, f.status = "ok";
    db::FitReportRow row;
    CopyVerdictKey(row, f);
    expect_key(row);
    EXPECT_EQ(row.status, "");
    analysis_t a{};
    CopyVerdictKey(a, row);
    expect_key(a);
    EXPECT_EQ(a.outcome, "");
}

TEST(RecordMapper, TheClosedLoopsAnalysisKeepsItsRunAndIsEssential) {
    // GIVEN the run in force R9 and an ANALYSIS_ message of run R1 (sent after R1's stop)
    RecordMapper m(MapperOptions::Defaults(), "R9");
    analysis_t a{};
    a.sensor_id = "U1", a.run_id = "R1", a.coeff_set_id = 42, a.source = "closed-loop";
    a.is_final = true, a.outcome = "explained", a.headline = "missing effect: supply, explained";
    a.rate_rms_dps_before = 0.2, a.rate_rms_dps_after = 0.02, a.result_json = "{}";
    const Mapped out = MapMsg(m, "ANALYSIS_U1", a);
    // THEN it is a ClosedLoopRow of R1, every field kept, never dropped by the queue
    ASSERT_TRUE(out.row);
    const auto& r = std::get<db::ClosedLoopRow>(*out.row);
    EXPECT_EQ(r.run_id, "R1");
    EXPECT_EQ(r.coeff_set_id, 42);
    EXPECT_EQ(r.source, "closed-loop");
    EXPECT_EQ(r.headline, a.headline);
    EXPECT_DOUBLE_EQ(r.rate_rms_dps_after, 0.02);
    EXPECT_EQ(r.recv_utime, 7);
    EXPECT_TRUE(out.essential);
}

TEST(RecordMapper, NoiseEstimatesAndFitReportsKeepTheirRunAndAreEssential) {
    RecordMapper m(MapperOptions::Defaults(), "R9");
    noise_t n{};
    n.sensor_id = "U1";
    n.run_id = "R1";
    n.bias_instability_v = 5e-5;
    n.tau_s = {0.1, 1.0};
    n.adev_v = {1e-3, 3e-4};
    n.adev_lo_v = n.adev_hi_v = n.edf = {1, 1};
    n.num_taus = 2;
    Mapped a = MapV5(m, "NOISE_U1", n);
    ASSERT_TRUE(a.row);
    const auto& nr = std::get<db::NoiseRow>(*a.row);
    EXPECT_EQ(nr.run_id, "R1");
    EXPECT_EQ(nr.adev_v, n.adev_v);
    EXPECT_TRUE(a.essential);
    fit_report_t f{};
    f.sensor_id = "U1";
    f.run_id = "R1";
    f.coeff_set_id = 42;
    f.is_final = true;
    f.status = "partial";
    fit_exclusion_t x{};
    x.kind = "rotation";
    x.item_id = 7;
    f.excluded = {x};
    f.num_excluded = 1;
    Mapped b = MapV5(m, "FIT_U1", f);
    ASSERT_TRUE(b.row);
    const auto& fr = std::get<db::FitReportRow>(*b.row);
    EXPECT_EQ(fr.run_id, "R1");
    EXPECT_TRUE(fr.is_final);
    ASSERT_EQ(fr.excluded.size(), 1u);
    EXPECT_EQ(fr.excluded[0].item_id, 7);
    EXPECT_TRUE(b.essential);
    // a truncated report is a decode error, kept raw
    auto bytes = EncodeMsg(f);
    bytes.resize(bytes.size() - 5);
    Mapped bad = m.Map("FIT_U1", bytes.data(), static_cast<int>(bytes.size()), 6);
    EXPECT_EQ(bad.loss.decode_errors, 1);
    EXPECT_TRUE(std::holds_alternative<db::RawEventRow>(*bad.row));
}

}  // namespace
}  // namespace gyrocal::recorder
