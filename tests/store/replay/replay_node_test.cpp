// gyrocal-replay's node in one process over memq:// (LCM's in-process provider): the stored run of
// source_run.hpp published on the node's own bus at speed 1000 (its 2 s in 2 ms). Known truth:
// the rows written; every one comes back once, in reception order, with its values; --as-run
// renames the run. No sleep: Run() returns after the last row and what it published last is
// handled after. Its timing and a second recorder storing the same run again, with real
// processes: replay_process_test.cpp.
#include "store/replay/replay_node.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <string>
#include <vector>

#include "gyrocal/chamber_state_t.hpp"
#include "gyrocal/encoder_sample_t.hpp"
#include "gyrocal/gyro_sample_t.hpp"
#include "gyrocal/run_event_t.hpp"
#include "lcmtypes/channels/channels.hpp"
#include "tests/lcmtypes/bus/bus_wait.hpp"
#include "tests/store/replay/source_run.hpp"
#include "tests/store/scratch_db.hpp"

namespace gyrocal::testing {
namespace {

using namespace std::chrono_literals;

struct Heard {
    std::vector<gyro_sample_t> gyro;
    std::vector<encoder_sample_t> encoder;
    std::vector<chamber_state_t> chamber;
    std::vector<run_event_t> events;
};

// Replays run RR of `db` with `as_run`; what the node published.
Heard Replay(const std::string& db, const std::string& as_run, int64_t* published) {
    replay::ReplayOptions o = replay::ReplayOptions::Defaults();
    o.db_path = db;
    o.run_id = "RR";
    o.as_run = as_run;
    o.lcm_url = "memq://";
    o.speed = 1000;
    replay::ReplayNode node(o);
    Heard h;
    CollectInto(node.bus(), channels::AllSensors(channels::kGyroPrefix), h.gyro);
    CollectInto(node.bus(), std::string(channels::kEncoder), h.encoder);
    CollectInto(node.bus(), std::string(channels::kChamberState), h.chamber);
    CollectInto(node.bus(), std::string(channels::kRunEvent), h.events);
    EXPECT_EQ(node.Run(), 0);
    EXPECT_TRUE(HandleUntil(
        node.bus(), [&] { return !node.bus().Handle(0ms); }, 10'000ms, 0ms));
    *published = node.published();
    return h;
}

TEST(ReplayNode, PublishesEveryStoredRowOnceWithItsValues) {
    const std::string db = FreshDbPath("replay_node.db");
    WriteSourceRun(db);
    int64_t published = 0;
    const Heard h = Replay(db, "", &published);
    // start + 2 x kSamples gyro + kSamples encoder + chamber + stop
    EXPECT_EQ(published, 2 + 3 * kSamples + 1);
    ASSERT_EQ(h.gyro.size(), static_cast<size_t>(2 * kSamples));
    for (int64_t i = 0; i < kSamples; ++i) {
        for (int k = 0; k < 2; ++k) {
            const gyro_sample_t& g = h.gyro[static_cast<size_t>(2 * i + k)];
            SCOPED_TRACE(g.sensor_id + " " + std::to_string(i));
            EXPECT_EQ(g.sensor_id, k == 0 ? "A" : "B");
            EXPECT_EQ(g.seq, i);
            EXPECT_EQ(g.utime, 1000000000000000 + i * 5000);
            EXPECT_EQ(g.gyro_v, 2.5 + 1e-6 * static_cast<double>(i));
            EXPECT_EQ(g.temp_c, 25.0);
            EXPECT_TRUE(std::isnan(g.supply_v));
        }
    }
    ASSERT_EQ(h.encoder.size(), static_cast<size_t>(kSamples));
    for (int64_t i = 0; i < kSamples; ++i) {
        EXPECT_EQ(h.encoder[static_cast<size_t>(i)].counts, i);
        EXPECT_EQ(h.encoder[static_cast<size_t>(i)].seq, i);
    }
    EXPECT_EQ(h.chamber.size(), 1u);
    ASSERT_EQ(h.events.size(), 2u);
    EXPECT_EQ(h.events[0].event, "start");
    EXPECT_EQ(h.events[0].run_id, "RR");
    EXPECT_EQ(h.events[0].config_json, R"({"k":1})");
    EXPECT_EQ(h.events[1].event, "stop");
}

TEST(ReplayNode, AsRunRenamesTheRun) {
    const std::string db = FreshDbPath("replay_node_as.db");
    WriteSourceRun(db);
    int64_t published = 0;
    const Heard h = Replay(db, "RR-replay", &published);
    ASSERT_EQ(h.events.size(), 2u);
    for (const run_event_t& e : h.events) EXPECT_EQ(e.run_id, "RR-replay");
    EXPECT_EQ(h.gyro.size(), static_cast<size_t>(2 * kSamples));
}

TEST(ReplayNode, AnUnknownRunIsAnError) {
    const std::string db = FreshDbPath("replay_node_unknown.db");
    WriteSourceRun(db);
    replay::ReplayOptions o = replay::ReplayOptions::Defaults();
    o.db_path = db;
    o.run_id = "NOPE";
    o.lcm_url = "memq://";
    EXPECT_ANY_THROW(replay::ReplayNode node(o));
}

}  // namespace
}  // namespace gyrocal::testing
