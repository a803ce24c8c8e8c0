// The recorder beside the real simulated rig (built only when gyrocal-sim-rig is in the build):
// every message the rig published is in the database, sample streams without gaps.
#include <gtest/gtest.h>

#include "gyrocal/status_t.hpp"
#include "tests/store/recorder/recorder_harness.hpp"

namespace gyrocal::testing {
namespace {

using namespace std::chrono_literals;

TEST(RecorderWithRig, StoresEveryMessageTheRigPublished) {
    const std::string db = FreshDbPath("rig_e2e.db");
    const std::string url = UrlForPort(7768);
    RecorderOnBus r(db, url);
    ASSERT_TRUE(r.Listening());
    int64_t rig_published = -1;
    launch::ChildProcess rig(
        {std::string(GYROCAL_BIN_DIR) + "/gyrocal-sim-rig", "--lcm-url", url, "--mode", "builtin",
         "--speed", "50", "--duration-s", "40", "--units", "4"},
        "", db + ".rig.err");
    r.bus.Subscribe<status_t>("STATUS", [&](const status_t& s, const std::string&) {
        if (s.pid == rig.pid()) rig_published = s.published;  // the last heartbeat counts itself
    });
    std::optional<launch::ExitStatus> st;
    const auto end = std::chrono::steady_clock::now() + 30s;
    while (!(st = rig.Poll()) && std::chrono::steady_clock::now() < end) r.bus.Handle(20ms);
    ASSERT_TRUE(st && st->exited && st->code == 0) << (st ? st->Describe() : "rig still running");
    for (int i = 0; i < 10; ++i) r.bus.Handle(20ms);  // its final heartbeat
    ASSERT_GT(rig_published, 0);
    const std::string stored_sql =
        "SELECT (SELECT count(*) FROM gyro_samples) + (SELECT count(*) FROM encoder_samples) + "
        "(SELECT count(*) FROM chamber_states) + (SELECT count(*) FROM power_states) + "
        "(SELECT count(*) FROM status WHERE pid = " +
        std::to_string(rig.pid()) + " AND process = 'gyrocal-sim-rig')";
    EXPECT_EQ(WaitForCount(db, stored_sql, rig_published, 10s), rig_published);
    EXPECT_EQ(r.rec.Stop().code, 0);
    // Every unit's power-on time (the rig's start) is announced every 10 s: t = 0, 10, .. 40 s.
    EXPECT_EQ(Count(db,
                    "SELECT count(*) FROM power_states WHERE power_on_utime = "
                    "(SELECT min(utime) FROM gyro_samples)"),
              4 * 5);
    // 40 simulated seconds at 100 Hz: 4001 samples per unit (t = 0 .. 40 s), seq without holes.
    EXPECT_EQ(Count(db,
                    "SELECT count(*) FROM (SELECT sensor_id FROM gyro_samples GROUP BY "
                    "sensor_id HAVING count(*) = max(seq) + 1 AND min(seq) = 0)"),
              4);
    EXPECT_EQ(Count(db,
                    "SELECT coalesce(sum(seq_gaps + queue_drops + decode_errors), 0) "
                    "FROM losses"),
              0);
}

}  // namespace
}  // namespace gyrocal::testing
