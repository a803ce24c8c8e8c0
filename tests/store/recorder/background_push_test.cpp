// gyrocal-recorder --push-to (store/recorder/node/background_push.hpp): the real recorder process
// on its own multicast port (7765) and a real PostgreSQL server (tests/store/pg_server.hpp). When a
// run ends on the bus the recorder starts `gyrocal push` in the background and goes on recording:
// the ended run arrives at the centre whole (every table equal to the station's) while the next
// run's samples, published meanwhile, are all stored; the URL's password is nowhere in the
// station file.
#include <gtest/gtest.h>
#include <signal.h>

#include <fstream>
#include <sstream>

#include "lcmtypes/channels/channels.hpp"
#include "store/db/central_db.hpp"
#include "store/db/query.hpp"
#include "tests/lcmtypes/bus/flow_pacer.hpp"
#include "tests/lcmtypes/message_builders.hpp"
#include "tests/store/pg_server.hpp"
#include "tests/store/recorder/recorder_harness.hpp"
#include "tests/store/table_digest.hpp"
#include "tests/support/wait/wait_until.hpp"

namespace gyrocal::testing {
namespace {

using namespace std::chrono_literals;
namespace st = gyrocal::db;

// Publishes `n` samples of each unit, each 10 handled by the recorder before the next (its
// answer to a flow mark), so the kernel's socket buffer never overflows.
void PublishSamples(bus::Bus& bus, FlowPacer& pacer, const std::vector<std::string>& units,
                    int64_t first, int64_t n) {
    int k = 0;
    for (int64_t s = first; s < first + n; ++s) {
        for (const auto& u : units) ASSERT_TRUE(bus.Publish(channels::Gyro(u), Gyro(u, s)));
        if (++k % 10 == 0) {
            ASSERT_TRUE(pacer.Sync()) << "the recorder answered no flow mark";
        }
    }
}

TEST(RecorderBackgroundPush, ARunEndingIsPushedWhileTheRecorderGoesOnRecording) {
    PgServer& server = SharedPgServer();
    server.EnsureRole("bg_pusher", "bg-pusher-pw-42");
    const std::string db_name = server.NewDatabase("bgpush");
    st::InitCentral(server.Url(db_name));
    st::GrantCentral(server.Url(db_name), "bg_pusher", false, false);
    const std::string url = server.Url(db_name, "bg_pusher", "bg-pusher-pw-42");
    const std::string station = FreshDbPath("background_push.db");
    RecorderOnBus r(station, UrlForPort(7765), {"--push-to", url});
    ASSERT_TRUE(r.Listening());
    FlowPacer pacer(r.bus, "gyrocal-recorder");
    const std::vector<std::string> units = {"B1", "B2"};
    // WHEN run BG1 ends, and BG2 starts and records at once
    ASSERT_TRUE(r.bus.Publish(std::string(channels::kRunEvent), RunEvent("BG1", "start", units)));
    PublishSamples(r.bus, pacer, units, 0, 2000);
    ASSERT_TRUE(r.bus.Publish(std::string(channels::kRunEvent), RunEvent("BG1", "stop", units)));
    ASSERT_TRUE(r.bus.Publish(std::string(channels::kRunEvent), RunEvent("BG2", "start", units)));
    PublishSamples(r.bus, pacer, units, 2000, 3000);
    // THEN BG1 reaches the centre (bounded wait: the push waits for the stop's commit, 200 ms)
    std::string outcome;
    WaitUntil(
        [&] {
            outcome = server.Query(db_name, "SELECT outcome FROM runs WHERE run_id = 'BG1'");
            return outcome == "stop";
        },
        60s, 200ms);
    ASSERT_EQ(outcome, "stop") << launch::ReadLog(station + ".recorder.err");
    r.rec.Signal(SIGTERM);
    const auto exit = r.rec.Wait(20s);
    ASSERT_TRUE(exit.has_value());
    EXPECT_EQ(exit->code, 0);
    // ... whole, and the recorder lost nothing of BG2 meanwhile
    auto s = st::OpenForQuery(station);
    auto c = st::OpenForQuery(server.Url(db_name));
    EXPECT_EQ(RunDigests(*c, *s, "BG1"), RunDigests(*s, *s, "BG1"));
    EXPECT_EQ(st::GetRun(*s, "BG1").gyro_samples, 2 * 2000);
    EXPECT_EQ(st::GetRun(*s, "BG2").gyro_samples, 2 * 3000);
    EXPECT_EQ(st::GetRun(*c, "BG1").gyro_samples, 2 * 2000);
    // BG2 is open: not pushed (its own end would push it)
    EXPECT_EQ(server.Query(db_name, "SELECT count(*) FROM runs WHERE run_id = 'BG2'"), "0");
    const std::string log = launch::ReadLog(station + ".recorder.err");
    EXPECT_NE(log.find("pushing it in the background"), std::string::npos) << log;
    EXPECT_EQ(log.find("bg-pusher-pw-42"), std::string::npos) << log;
    std::ifstream f(station, std::ios::binary);
    std::stringstream bytes;
    bytes << f.rdbuf();
    EXPECT_EQ(bytes.str().find("bg-pusher-pw-42"), std::string::npos);
}

}  // namespace
}  // namespace gyrocal::testing
