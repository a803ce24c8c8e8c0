// The STATUS heartbeat over memq:// (LCM's in-process provider): what it carries, when Tick
// publishes, the node loop's first and last heartbeat; and the rate-limited warnings.
#include "lcmtypes/process/status.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <map>
#include <stdexcept>
#include <thread>
#include <vector>

#include "gyrocal/status_t.hpp"
#include "lcmtypes/channels/channels.hpp"

namespace gyrocal {
namespace {

using namespace std::chrono_literals;

// Every STATUS delivered on `bus` from construction on, in order.
class Heartbeats {
public:
    explicit Heartbeats(bus::Bus& bus) : bus_(bus) {
        bus.Subscribe<status_t>(
            std::string(channels::kStatus),
            [this](const status_t& s, const std::string&) { seen_.push_back(s); });
    }
    const std::vector<status_t>& Drain() {
        while (bus_.Handle(20ms)) {
        }
        return seen_;
    }

private:
    bus::Bus& bus_;
    std::vector<status_t> seen_;
};

TEST(StatusReporter, AHeartbeatCarriesTheProcessItsStateAndEveryCount) {
    bus::Bus bus(bus::BusOptions{"memq://"});
    Heartbeats heartbeats(bus);
    process::StatusReporter status(bus, "gyrocal-test", 1h);
    status.set_state("waiting");
    status.Reject("range", "10 C narrower than 20 C");
    status.AddQueueDrops(2);
    status.AddSeqGaps(3);
    status.AddDecodeErrors(4);
    status.SetExtra("points", 7);
    status.PublishNow();
    const std::vector<status_t>& seen = heartbeats.Drain();
    ASSERT_EQ(seen.size(), 1u);
    const status_t& s = seen[0];
    EXPECT_EQ(s.process, "gyrocal-test");
    EXPECT_EQ(s.host, process::HostName());
    EXPECT_EQ(s.pid, getpid());
    EXPECT_EQ(s.state, "waiting");
    EXPECT_EQ(s.rejected, 1);
    EXPECT_EQ(status.rejected(), 1);
    EXPECT_EQ(s.last_reject, "range: 10 C narrower than 20 C");
    EXPECT_EQ(s.queue_drops, 2);
    EXPECT_EQ(s.seq_gaps, 3);       // the bus counted none itself
    EXPECT_EQ(s.decode_errors, 4);  // likewise
    EXPECT_EQ(s.published, 1);      // the heartbeat counts itself
    // Its own extras, then the bus's handler failures, backward steps and failed publishes, by
    // name.
    EXPECT_EQ(s.extra_names, (std::vector<std::string>{"handler_errors", "points", "publish_errors",
                                                       "seq_backwards"}));
    EXPECT_EQ(s.extra_values, (std::vector<double>{0, 7, 0, 0}));
    EXPECT_EQ(s.num_extra, 4);
}

// Issue 27: a handler's failure stops the node loop as before, but its last heartbeat counts it,
// in all and per channel, and says what it was.
TEST(RunLoop, AFailedHandlerIsCountedInTheLastHeartbeat) {
    bus::Bus bus(bus::BusOptions{"memq://"});
    Heartbeats heartbeats(bus);
    bus.Subscribe<status_t>(
        "BOOM", [](const status_t&, const std::string&) { throw std::runtime_error("boom"); });
    bus.Publish("BOOM", status_t{});
    process::StatusReporter status(bus, "gyrocal-test", 1h);
    EXPECT_THROW(process::RunLoop(bus, status, {}, 1ms), std::runtime_error);
    const std::vector<status_t>& seen = heartbeats.Drain();
    ASSERT_EQ(seen.size(), 2u);
    EXPECT_EQ(seen[0].state, "running");
    const status_t& last = seen[1];
    EXPECT_EQ(last.state, "failed");
    EXPECT_EQ(last.last_reject, "handler_error: channel BOOM: boom");
    std::map<std::string, double> extra;
    for (size_t i = 0; i < last.extra_names.size(); ++i)
        extra[last.extra_names[i]] = last.extra_values[i];
    EXPECT_EQ(extra["handler_errors"], 1);
    EXPECT_EQ(extra["handler_errors:BOOM"], 1);
}

TEST(StatusReporter, TickPublishesOncePerPeriod) {
    bus::Bus bus(bus::BusOptions{"memq://"});
    Heartbeats heartbeats(bus);
    process::StatusReporter status(bus, "gyrocal-test", 200ms);
    status.Tick();                       // the first: nothing published yet
    status.Tick();                       // within the period
    std::this_thread::sleep_for(250ms);  // time itself: what is tested is the period
    status.Tick();                       // a period later
    EXPECT_EQ(heartbeats.Drain().size(), 2u);
}

TEST(RunLoop, SaysRunningAtTheStartAndPublishesAgainWhenDone) {
    bus::Bus bus(bus::BusOptions{"memq://"});
    Heartbeats heartbeats(bus);
    process::StatusReporter status(bus, "gyrocal-test", 1h);
    int polls = 0;
    process::RunLoop(
        bus, status, [&polls] { return ++polls > 3; }, 1ms);
    EXPECT_EQ(polls, 4);
    const std::vector<status_t>& seen = heartbeats.Drain();
    ASSERT_EQ(seen.size(), 2u);
    EXPECT_EQ(seen[0].state, "running");
    EXPECT_EQ(seen[1].state, "running");
}

TEST(RateLimitedLog, RepeatsWithinASecondAreCountedAndSaidWithTheNext) {
    process::RateLimitedLog log("gyrocal-test");
    ::testing::internal::CaptureStderr();
    log.Warn("gap", "first");
    log.Warn("gap", "second");            // within the second: suppressed
    log.Warn("other", "third");           // another key: its own limit
    std::this_thread::sleep_for(1100ms);  // time itself: past the one-second limit
    log.Warn("gap", "fourth");
    EXPECT_EQ(::testing::internal::GetCapturedStderr(),
              "gyrocal-test: warning: first\n"
              "gyrocal-test: warning: third\n"
              "gyrocal-test: warning: fourth (1 more like it suppressed)\n");
}

}  // namespace
}  // namespace gyrocal
