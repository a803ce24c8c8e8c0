// gyrocal-replay publishes a stored run with its timing; a second recorder stores exactly the
// same samples again.
#include <gtest/gtest.h>

#include <cmath>

#include "store/db/writer.hpp"
#include "tests/store/recorder/recorder_harness.hpp"
#include "tests/store/replay/source_run.hpp"

namespace gyrocal::testing {
namespace {

using namespace std::chrono_literals;

TEST(Replay, RepublishesTheRunWithItsTimingAndARecorderStoresItAgain) {
    const std::string src = FreshDbPath("replay_src.db");
    const std::string dst = FreshDbPath("replay_dst.db");
    WriteSourceRun(src);
    const std::string url = UrlForPort(7764);
    RecorderOnBus r(dst, url);
    ASSERT_TRUE(r.Listening());

    // Speed 4: the 2 s run should take 0.5 s. Allowance: process start and database open
    // (< 100 ms) plus scheduling on a loaded machine (300 ms); never shorter than the span/4.
    const auto t0 = std::chrono::steady_clock::now();
    launch::ChildProcess replay({std::string(GYROCAL_BIN_DIR) + "/gyrocal-replay", "RR", "--db",
                                 src, "--speed", "4", "--lcm-url", url},
                                "", dst + ".replay.err");
    const auto st = replay.Wait(20s);
    const auto took = std::chrono::steady_clock::now() - t0;
    ASSERT_TRUE(st && st->exited && st->code == 0);
    EXPECT_GE(took, std::chrono::microseconds(kSpanUs / 4));
    EXPECT_LE(took, std::chrono::microseconds(kSpanUs / 4) + 400ms);

    EXPECT_EQ(WaitForCount(dst, "SELECT count(*) FROM gyro_samples WHERE run_id = 'RR'",
                           2 * kSamples, 10s),
              2 * kSamples);
    EXPECT_EQ(r.rec.Stop().code, 0);
    EXPECT_EQ(Count(dst, "SELECT count(*) FROM encoder_samples WHERE run_id = 'RR'"), kSamples);
    EXPECT_EQ(Count(dst, "SELECT count(*) FROM chamber_states WHERE run_id = 'RR'"), 1);
    EXPECT_EQ(Count(dst,
                    "SELECT count(*) FROM runs WHERE run_id = 'RR' AND outcome = 'stop' "
                    "AND config_json = '{\"k\":1}'"),
              1);
    // Same values: seq, utime, gyro_v of every sample; NaN supply is NaN (NULL) again.
    db::Db a(src, db::Db::Mode::kReadOnly);
    db::Db b(dst, db::Db::Mode::kReadOnly);
    const char* q =
        "SELECT sensor_id, seq, utime, gyro_v, supply_v IS NULL FROM gyro_samples "
        "ORDER BY sensor_id, seq";
    db::Stmt sa(a, q), sb(b, q);
    int64_t compared = 0;
    while (sa.Step()) {
        ASSERT_TRUE(sb.Step());
        EXPECT_EQ(sa.Text(0), sb.Text(0));
        EXPECT_EQ(sa.Int(1), sb.Int(1));
        EXPECT_EQ(sa.Int(2), sb.Int(2));
        EXPECT_EQ(sa.Real(3), sb.Real(3));
        EXPECT_EQ(sb.Int(4), 1);
        ++compared;
    }
    EXPECT_EQ(compared, 2 * kSamples);
    EXPECT_EQ(Count(dst, "SELECT coalesce(sum(seq_gaps), 0) FROM losses"), 0);
}

TEST(Replay, AsRunKeepsAReplayIntoTheSameDatabaseApart) {
    const std::string db = FreshDbPath("replay_same.db");
    WriteSourceRun(db);
    const std::string url = UrlForPort(7766);
    RecorderOnBus r(db, url);
    ASSERT_TRUE(r.Listening());
    launch::ChildProcess replay({std::string(GYROCAL_BIN_DIR) + "/gyrocal-replay", "RR", "--db", db,
                                 "--speed", "20", "--as-run", "RR-replay", "--lcm-url", url},
                                "", db + ".replay.err");
    const auto st = replay.Wait(20s);
    ASSERT_TRUE(st && st->exited && st->code == 0);
    EXPECT_EQ(WaitForCount(db, "SELECT count(*) FROM gyro_samples WHERE run_id = 'RR-replay'",
                           2 * kSamples, 10s),
              2 * kSamples);
    EXPECT_EQ(r.rec.Stop().code, 0);
    EXPECT_EQ(Count(db, "SELECT count(*) FROM gyro_samples WHERE run_id = 'RR'"), 2 * kSamples);
    EXPECT_EQ(
        Count(db, "SELECT count(*) FROM runs WHERE run_id = 'RR-replay' AND outcome = 'stop'"), 1);
}

TEST(Replay, UnknownRunAndBadOptions) {
    const std::string src = FreshDbPath("replay_bad.db");
    WriteSourceRun(src);
    const std::string bin = std::string(GYROCAL_BIN_DIR) + "/gyrocal-replay";
    launch::ChildProcess unknown({bin, "NOPE", "--db", src, "--lcm-url", UrlForPort(7765)}, "",
                                 src + ".err1");
    auto st = unknown.Wait(10s);
    ASSERT_TRUE(st);
    EXPECT_EQ(st->code, 1);
    launch::ChildProcess bad({bin, "RR", "--db", src, "--speed", "-3"}, "", src + ".err2");
    st = bad.Wait(10s);
    ASSERT_TRUE(st);
    EXPECT_EQ(st->code, 2);
}

}  // namespace
}  // namespace gyrocal::testing
