// The real gyrocal-recorder process on its own multicast port: every message published is in the
// database, in its table and its run; unknown types land in raw_events; provenance is complete;
// a restarted recorder continues the open run.
#include <gtest/gtest.h>

#include <fstream>
#include <iterator>

#include "lcmtypes/channels/channels.hpp"
#include "store/db/analyses.hpp"
#include "store/db/model_rows.hpp"
#include "tests/lcmtypes/bus/flow_pacer.hpp"
#include "tests/lcmtypes/message_builders.hpp"
#include "tests/store/recorder/recorder_harness.hpp"

namespace gyrocal::testing {
namespace {

using namespace std::chrono_literals;

// Publishes in bursts of 20, each handled by the recorder before the next (its answer to a flow
// mark), so the kernel's socket buffer never overflows (what is tested here is the recorder, not
// UDP).
class Publisher {
public:
    explicit Publisher(bus::Bus& bus) : bus_(bus), pacer_(bus, "gyrocal-recorder") {}
    template <class Msg>
    void Send(const std::string& channel, const Msg& m) {
        ASSERT_TRUE(bus_.Publish(channel, m));
        ++count_[channel];
        if (++n_ % 20 == 0) {
            ASSERT_TRUE(pacer_.Sync()) << "the recorder answered no flow mark";
        }
    }
    void SendRaw(const std::string& channel, const std::vector<uint8_t>& b) {
        ASSERT_TRUE(bus_.PublishRaw(channel, b.data(), static_cast<int>(b.size())));
        ++count_[channel];
    }
    int64_t count(const std::string& channel) { return count_[channel]; }

private:
    bus::Bus& bus_;
    FlowPacer pacer_;
    std::map<std::string, int64_t> count_;
    int64_t n_ = 0;
};

TEST(RecorderProcess, EveryPublishedMessageIsStoredInItsTableAndRun) {
    const std::string db = FreshDbPath("full_stream.db");
    RecorderOnBus r(db, UrlForPort(7760));
    ASSERT_TRUE(r.Listening()) << "recorder did not come up";

    // GIVEN a run of 3 sensors: samples before the start (no run), in the run, after the stop.
    const std::vector<std::string> ids = {"S01", "S02", "S03"};
    const int64_t kBefore = 50, kIn = 1500, kAfter = 40;
    Publisher pub(r.bus);
    int64_t seq = 0;
    for (; seq < kBefore; ++seq) {
        for (const auto& id : ids) pub.Send(channels::Gyro(id), Gyro(id, seq));
    }
    pub.Send(std::string(channels::kRunEvent), RunEvent("R1", "start", ids));
    pub.Send(std::string(channels::kChamberCmd), ChamberCmd("R1"));
    for (int64_t i = 0; i < kIn; ++i, ++seq) {
        for (const auto& id : ids) {
            pub.Send(channels::Gyro(id), Gyro(id, seq));
            pub.Send(channels::Rate(id), Rate(id, seq));
        }
        pub.Send(std::string(channels::kEncoder), Encoder(seq));
        if (i % 100 == 0) {
            pub.Send(std::string(channels::kChamberState), Chamber(i / 100));
            pub.Send(std::string(channels::kStatus), Status("test"));
            pub.Send(channels::Stability("S01"), PlateauState("S01"));
        }
    }
    pub.Send(std::string(channels::kTurntableCmd), TurntableCmd("R1"));
    // Plateaus and a rotation over stored sample ranges, and a coefficient set using them.
    std::vector<int64_t> plateau_ids;
    for (int64_t k = 0; k < 3; ++k) {
        const plateau_t p = Plateau("S01", "R1", kBefore + 100 + 300 * k, kBefore + 199 + 300 * k);
        plateau_ids.push_back(p.plateau_id);
        pub.Send(channels::Plateau("S01"), p);
    }
    const sensitivity_point_t sp = Sensitivity("S01", "R1", kBefore + 1000, kBefore + 1049);
    pub.Send(channels::Sensitivity("S01"), sp);
    pub.Send(channels::Coeffs("S01"), Coeffs("S01", "R1", 77, plateau_ids, {sp.rotation_id}));
    // Unknown types: bytes with a fingerprint no gyrocal type has.
    std::vector<uint8_t> unknown = {0x01, 0x23, 0x45, 0x67, 0x89, 0xab, 0xcd, 0xef, 'h', 'i'};
    for (int i = 0; i < 5; ++i) pub.SendRaw("SOMEONE_ELSES_TYPE", unknown);
    pub.Send(std::string(channels::kRunEvent), RunEvent("R1", "stop", ids));
    for (int64_t i = 0; i < kAfter; ++i, ++seq) {
        for (const auto& id : ids) pub.Send(channels::Gyro(id), Gyro(id, seq));
    }

    // WHEN the recorder has committed it all and is stopped normally
    const int64_t gyro_total = (kBefore + kIn + kAfter) * 3;
    EXPECT_EQ(WaitForCount(db, "SELECT count(*) FROM gyro_samples", gyro_total, 10s), gyro_total);
    const launch::ExitStatus st = r.rec.Stop();
    EXPECT_TRUE(st.exited && st.code == 0) << st.Describe();

    // THEN each channel's count equals what was published, in the right run
    for (const auto& id : ids) {
        EXPECT_EQ(Count(db, "SELECT count(*) FROM gyro_samples WHERE sensor_id = '" + id + "'"),
                  pub.count(channels::Gyro(id)));
        EXPECT_EQ(Count(db, "SELECT count(*) FROM rates WHERE sensor_id = '" + id + "'"),
                  pub.count(channels::Rate(id)));
        EXPECT_EQ(Count(db,
                        "SELECT count(*) FROM gyro_samples WHERE run_id = 'R1' AND "
                        "sensor_id = '" +
                            id + "'"),
                  kIn);
        EXPECT_EQ(Count(db,
                        "SELECT count(*) FROM gyro_samples WHERE run_id = '' AND "
                        "sensor_id = '" +
                            id + "'"),
                  kBefore + kAfter);
    }
    EXPECT_EQ(Count(db, "SELECT count(*) FROM encoder_samples"), pub.count("ENCODER"));
    EXPECT_EQ(Count(db, "SELECT count(*) FROM chamber_states"), pub.count("CHAMBER_STATE"));
    EXPECT_EQ(Count(db, "SELECT count(*) FROM chamber_cmds"), pub.count("CHAMBER_CMD"));
    EXPECT_EQ(Count(db, "SELECT count(*) FROM turntable_cmds"), pub.count("TURNTABLE_CMD"));
    EXPECT_EQ(Count(db, "SELECT count(*) FROM plateau_states"), pub.count("STABILITY_S01"));
    EXPECT_EQ(Count(db, "SELECT count(*) FROM status WHERE process = 'test'"), pub.count("STATUS"));
    EXPECT_EQ(Count(db, "SELECT count(*) FROM plateaus"), pub.count("PLATEAU_S01"));
    EXPECT_EQ(Count(db, "SELECT count(*) FROM sensitivity_points"), pub.count("SENSITIVITY_S01"));
    EXPECT_EQ(Count(db, "SELECT count(*) FROM coeff_sets"), pub.count("COEFFS_S01"));
    EXPECT_EQ(Count(db, "SELECT count(*) FROM run_events"), pub.count("RUN_EVENT"));
    EXPECT_EQ(Count(db, "SELECT count(*) FROM status WHERE process = 'gyrocal-recorder'") > 0,
              true);
    // Unknown types kept whole with their fingerprint.
    EXPECT_EQ(Count(db,
                    "SELECT count(*) FROM raw_events WHERE channel = 'SOMEONE_ELSES_TYPE' "
                    "AND reason = 'unknown_type' AND fingerprint = '0123456789abcdef' "
                    "AND length(data) = 10 AND run_id = 'R1'"),
              5);
    // The run: created by start with its provenance fields, closed by stop.
    EXPECT_EQ(Count(db,
                    "SELECT count(*) FROM runs WHERE run_id = 'R1' AND outcome = 'stop' AND "
                    "software_version = 'test-1.0' AND host = 'testhost' AND "
                    "command_line LIKE 'gyrocal calibrate%' AND "
                    "json_extract(config_json, '$.setpoints_c[2]') = 50 AND "
                    "stopped_utime IS NOT NULL"),
              1);
    EXPECT_EQ(Count(db, "SELECT count(*) FROM run_sensors WHERE run_id = 'R1'"), 3);
    // Nothing lost on this clean stream.
    EXPECT_EQ(Count(db,
                    "SELECT coalesce(sum(seq_gaps + decode_errors + queue_drops), 0) "
                    "FROM losses"),
              0);
    // Provenance: every plateau and the rotation found, and each range holds exactly its samples.
    EXPECT_EQ(Count(db, "SELECT count(*) FROM v_coeff_provenance WHERE item_found = 1"), 4);
    EXPECT_EQ(Count(db, "SELECT count(*) FROM v_coeff_samples"), 3 * 100 + 50);
    EXPECT_EQ(Count(db,
                    "SELECT count(*) FROM (SELECT v.item_id FROM v_coeff_provenance v "
                    "JOIN v_coeff_samples s ON s.coeff_row_id = v.coeff_row_id AND "
                    "s.item_id = v.item_id AND s.kind = v.kind GROUP BY v.kind, v.item_id "
                    "HAVING count(*) = max(v.n_samples))"),
              4);
    EXPECT_EQ(Count(db,
                    "SELECT count(*) FROM recorder_sessions WHERE stopped_wall_utime IS NOT "
                    "NULL"),
              1);
}

TEST(RecorderProcess, RestartedRecorderContinuesTheOpenRunAndNoRatesSkipsRates) {
    const std::string db = FreshDbPath("restart.db");
    const std::string url = UrlForPort(7761);
    {
        RecorderOnBus first(db, url);
        ASSERT_TRUE(first.Listening());
        ASSERT_TRUE(
            first.bus.Publish(std::string(channels::kRunEvent), RunEvent("R9", "start", {"A"})));
        for (int64_t s = 0; s < 10; ++s)
            ASSERT_TRUE(first.bus.Publish(channels::Gyro("A"), Gyro("A", s)));
        EXPECT_EQ(WaitForCount(db, "SELECT count(*) FROM gyro_samples", 10, 10s), 10);
        EXPECT_EQ(first.rec.Stop().code, 0);
    }
    // GIVEN the run was not stopped WHEN a new recorder starts THEN its samples join R9.
    RecorderOnBus r(db, url, {"--no-rates"});
    ASSERT_TRUE(r.Listening());
    for (int64_t s = 10; s < 20; ++s) {
        ASSERT_TRUE(r.bus.Publish(channels::Gyro("A"), Gyro("A", s)));
        ASSERT_TRUE(r.bus.Publish(channels::Rate("A"), Rate("A", s)));
    }
    EXPECT_EQ(WaitForCount(db, "SELECT count(*) FROM gyro_samples WHERE run_id = 'R9'", 20, 10s),
              20);
    EXPECT_EQ(r.rec.Stop().code, 0);
    EXPECT_EQ(Count(db, "SELECT count(*) FROM rates"), 0);
    EXPECT_EQ(Count(db,
                    "SELECT resumed_run_id = 'R9' FROM recorder_sessions ORDER BY "
                    "session_id DESC LIMIT 1"),
              1);
}

TEST(RecorderProcess, UnwritableDbIsAOneLineErrorAndExitTwo) {
    launch::ChildProcess rec({std::string(GYROCAL_BIN_DIR) + "/gyrocal-recorder", "--db",
                              "/nonexistent-dir/x.db", "--lcm-url", UrlForPort(7762)},
                             "", FreshDbPath("unwritable.err"));
    const auto st = rec.Wait(10s);
    ASSERT_TRUE(st);
    EXPECT_TRUE(st->exited);
    EXPECT_EQ(st->code, 2);
}

TEST(RecorderProcess, NonGyrocalDatabaseIsRefused) {
    const std::string db = FreshDbPath("foreign.db");
    {
        db::Db d(db, db::Db::Mode::kReadWriteCreate);
        d.Exec("CREATE TABLE t(x)");
    }
    launch::ChildProcess rec({std::string(GYROCAL_BIN_DIR) + "/gyrocal-recorder", "--db", db,
                              "--lcm-url", UrlForPort(7762)},
                             "", db + ".err");
    const auto st = rec.Wait(10s);
    ASSERT_TRUE(st);
    EXPECT_EQ(st->code, 2);
}

// `gyrocal analyze --publish`: the extended set is stored directly with its analysis, then
// published for a live compensator; the recorder hears it and must not store it again. The
// fitter's re-publish of an unchanged set (same coeff_set_id) is kept once too; another source
// with the same id is another set.
TEST(RecorderProcess, ACoefficientSetIsKeptOncePerRunSensorIdAndSource) {
    const std::string db = FreshDbPath("coeff_once.db");
    RecorderOnBus r(db, UrlForPort(7767));
    ASSERT_TRUE(r.Listening());
    ASSERT_TRUE(r.bus.Publish(std::string(channels::kRunEvent), RunEvent("R5", "start", {"S01"})));
    ASSERT_EQ(WaitForCount(db, "SELECT count(*) FROM runs WHERE run_id = 'R5'", 1, 10s), 1);

    // GIVEN an analysis stored, with its extended set, while the recorder writes the same file
    coeff_set_t extended = Coeffs("S01", "R5", 77, {}, {});
    db::AnalysisRow a;
    a.run_id = "R5";
    a.sensor_id = "S01";
    a.verdict = "added temp_rate";
    db::StoredAnalysis stored;
    {
        auto rw = db::OpenForUpdate(db);
        stored = db::StoreAnalysis(*rw, a, &extended);
    }
    ASSERT_TRUE(stored.coeff_row_id);
    // WHEN it is published (twice), and the fitter's set with the same id (twice)
    extended.source = stored.source;
    const coeff_set_t fitter = Coeffs("S01", "R5", 77, {}, {});
    for (int k = 0; k < 2; ++k) {
        ASSERT_TRUE(r.bus.Publish(channels::Coeffs("S01"), extended));
        ASSERT_TRUE(r.bus.Publish(channels::Coeffs("S01"), fitter));
    }
    ASSERT_TRUE(r.bus.Publish(std::string(channels::kRunEvent), RunEvent("R5", "stop", {"S01"})));
    // (one writer, in order: once the stop is stored, the sets before it are too)
    ASSERT_EQ(WaitForCount(db, "SELECT count(*) FROM run_events WHERE run_id = 'R5'", 2, 10s), 2);
    EXPECT_EQ(r.rec.Stop().code, 0);

    // THEN one row per source, and the analysis points at the row it stored
    EXPECT_EQ(Count(db, "SELECT count(*) FROM coeff_sets"), 2);
    EXPECT_EQ(Count(db, "SELECT count(*) FROM coeff_sets WHERE source = 'fitter'"), 1);
    EXPECT_EQ(
        Count(db, "SELECT coeff_row_id FROM coeff_sets WHERE source = '" + stored.source + "'"),
        *stored.coeff_row_id);
    EXPECT_EQ(Count(db, "SELECT count(*) FROM coeff_terms WHERE coeff_row_id = " +
                            std::to_string(*stored.coeff_row_id)),
              3 + 2);  // not doubled
}

TEST(RecorderProcess, InvalidChannelRegexIsABadOptionNamingIt) {
    const std::string err = FreshDbPath("bad_regex.err");
    for (const std::string bad : {"GYRO_(", "*", "[a-"}) {
        launch::ChildProcess rec(
            {std::string(GYROCAL_BIN_DIR) + "/gyrocal-recorder", "--db",
             FreshDbPath("bad_regex.db"), "--channels", bad, "--lcm-url", UrlForPort(7762)},
            "", err);
        const auto st = rec.Wait(10s);
        ASSERT_TRUE(st);
        EXPECT_TRUE(st->exited);
        EXPECT_EQ(st->code, 2) << bad;
        std::ifstream f(err);
        const std::string text((std::istreambuf_iterator<char>(f)),
                               std::istreambuf_iterator<char>());
        EXPECT_NE(text.find("--channels"), std::string::npos) << text;
        EXPECT_NE(text.find("not a valid channel regex"), std::string::npos) << text;
    }
    // A valid one is accepted: the recorder comes up (its heartbeat) and stops normally.
    RecorderOnBus ok(FreshDbPath("good_regex.db"), UrlForPort(7769),
                     {"--channels", "GYRO_.*|RUN_EVENT"});
    ASSERT_TRUE(ok.Listening());
    EXPECT_EQ(ok.rec.Stop().code, 0);
}

}  // namespace
}  // namespace gyrocal::testing
