// Two real processes over UDP multicast (TTL 0): this test publishes, gyrocal-bus-probe listens
// and reports its counters in STATUS, which this test receives over the same group.
// Port 7701 is this file's own, so parallel tests never hear each other.
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <fstream>
#include <optional>
#include <sstream>
#include <thread>

#include "gyrocal/encoder_sample_t.hpp"
#include "gyrocal/gyro_sample_t.hpp"
#include "gyrocal/status_t.hpp"
#include "lcmtypes/bus/bus.hpp"
#include "lcmtypes/channels/channels.hpp"
#include "lcmtypes/launch/child_process.hpp"
#include "tests/lcmtypes/bus/bus_wait.hpp"

namespace gyrocal {
namespace {

using namespace std::chrono_literals;
const std::string kUrl = "udpm://239.255.76.67:7701?ttl=0&recv_buf_size=4194304";
const std::string kProbe = GYROCAL_BUS_PROBE;

// Waits (bounded) for a STATUS of the probe that satisfies `pred`.
std::optional<status_t> AwaitProbeStatus(bus::Bus& bus,
                                         const std::function<bool(const status_t&)>& pred,
                                         std::chrono::seconds limit) {
    std::optional<status_t> found;
    bus.Subscribe<status_t>(std::string(channels::kStatus),
                            [&](const status_t& s, const std::string&) {
                                if (s.process == "gyrocal-bus-probe" && pred(s)) found = s;
                            });
    testing::HandleUntil(
        bus, [&] { return found.has_value(); }, limit);
    return found;
}

TEST(BusMultiProcess, CountsSamplesGapsAndWrongTypesAcrossProcesses) {
    bus::Bus bus(bus::BusOptions{kUrl});
    launch::ChildProcess probe(
        {kProbe, "--lcm-url", kUrl, "--channel", "GYRO_MP", "--idle-exit-s", "20"});
    // GIVEN the probe is up (its first heartbeat arrived)
    {
        bus::Bus status_bus(bus::BusOptions{kUrl});
        ASSERT_TRUE(AwaitProbeStatus(
            status_bus, [](const status_t&) { return true; }, 10s))
            << "probe never sent STATUS";
    }
    // WHEN 200 samples are sent with seq 100..104 left out, and 3 encoder messages on its channel
    gyro_sample_t s;
    s.sensor_id = "MP";
    int sent = 0;
    for (int64_t seq = 0; seq < 200; ++seq) {
        if (seq >= 100 && seq < 105) continue;
        s.seq = seq;
        s.utime = seq * 10'000;
        ASSERT_TRUE(bus.Publish("GYRO_MP", s));
        ++sent;
    }
    encoder_sample_t wrong;
    for (int i = 0; i < 3; ++i) bus.Publish("GYRO_MP", wrong);
    // THEN its STATUS reports all of them, the 5 missing and the 3 that did not decode
    bus::Bus status_bus(bus::BusOptions{kUrl});
    auto st = AwaitProbeStatus(
        status_bus, [&](const status_t& x) { return x.received >= sent && x.decode_errors >= 3; },
        15s);
    ASSERT_TRUE(st.has_value()) << "probe never reported the samples";
    EXPECT_EQ(st->received, sent);
    EXPECT_EQ(st->seq_gaps, 5);
    EXPECT_EQ(st->decode_errors, 3);
    EXPECT_NE(st->last_reject.find("GYRO_MP"), std::string::npos) << st->last_reject;
    launch::ExitStatus ex = probe.Stop();
    EXPECT_TRUE(ex.exited) << ex.Describe();
    EXPECT_EQ(ex.code, 0);
}

TEST(BusMultiProcess, UnknownOptionIsExitCode2WithMessage) {
    const std::string err = ::testing::TempDir() + "probe_badopt.err";
    launch::ChildProcess probe({kProbe, "--no-such-option"}, "", err);
    auto ex = probe.Wait(10s);
    ASSERT_TRUE(ex.has_value());
    EXPECT_EQ(ex->code, 2);
    EXPECT_NE(launch::ReadLog(err).find("--no-such-option"), std::string::npos);
}

// A host without a multicast route: a fresh network namespace has only a down loopback.
// The process must exit 1 with the LCM loopback fix in its one-line message.
TEST(BusMultiProcess, NoMulticastRouteGivesTheFix) {
    if (geteuid() != 0) GTEST_SKIP() << "needs root to create a network namespace (ip netns)";
    const std::string ns = "gyrocal-noroute-" + std::to_string(getpid());
    ASSERT_EQ(std::system(("ip netns add " + ns).c_str()), 0);
    const std::string err = ::testing::TempDir() + "probe_noroute.err";
    launch::ChildProcess probe({"ip", "netns", "exec", ns, kProbe, "--lcm-url",
                                "udpm://239.255.76.67:7702?ttl=0", "--idle-exit-s", "2"},
                               "", err);
    auto ex = probe.Wait(15s);
    std::system(("ip netns delete " + ns).c_str());
    ASSERT_TRUE(ex.has_value());
    EXPECT_EQ(ex->code, 1) << launch::ReadLog(err);
    EXPECT_NE(launch::ReadLog(err).find("ip route add 224.0.0.0/4 dev lo"), std::string::npos)
        << launch::ReadLog(err);
}

}  // namespace
}  // namespace gyrocal
