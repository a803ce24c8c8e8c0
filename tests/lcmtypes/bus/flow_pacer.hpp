#pragma once
// A test's sender paced on a real process the way gyrocal's sources pace (lcmtypes/flow): after a
// burst, a flow mark; the process answers it once it has handled every message sent before it
// (its bus hands them over in arrival order). A bounded wait on that condition instead of a sleep
// that guesses how fast the receiver drains its socket.
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <string>

#include "gyrocal/flow_ack_t.hpp"
#include "gyrocal/flow_mark_t.hpp"
#include "lcmtypes/bus/bus.hpp"
#include "lcmtypes/channels/channels.hpp"
#include "lcmtypes/flow/flow_acker.hpp"
#include "tests/lcmtypes/bus/bus_wait.hpp"

namespace gyrocal::testing {

// Subscribes on construction; it must not move (the handler holds `this`).
class FlowPacer {
public:
    // `process`: the consumer whose answers count (its STATUS name, e.g. "gyrocal-plateau").
    FlowPacer(bus::Bus& bus, std::string process)
        : bus_(bus), process_(std::move(process)), host_(flow::ThisHost()), pid_(getpid()) {
        bus_.Subscribe<flow_ack_t>(
            std::string(channels::kFlowAck), [this](const flow_ack_t& a, const std::string&) {
                if (a.process == process_ && a.source_host == host_ && a.source_pid == pid_)
                    acked_ = std::max(acked_, a.mark_seq);
            });
    }
    FlowPacer(const FlowPacer&) = delete;
    FlowPacer& operator=(const FlowPacer&) = delete;

    // Marks what was sent so far, then handles the bus until the process has answered the mark
    // (it has handled everything before it) or `limit` has passed; whether it answered.
    bool Sync(std::chrono::milliseconds limit = std::chrono::milliseconds(10'000)) {
        flow_mark_t m{};
        m.utime = std::chrono::duration_cast<std::chrono::microseconds>(
                      std::chrono::system_clock::now().time_since_epoch())
                      .count();
        m.source = "gyrocal-test";
        m.host = host_;
        m.pid = pid_;
        m.mark_seq = ++mark_seq_;
        m.published = bus_.counters().published;
        m.data_utime = 0;
        bus_.Publish(std::string(channels::kFlowMark), m);
        return HandleUntil(
            bus_, [this] { return acked_ >= mark_seq_; }, limit, std::chrono::milliseconds(5));
    }

private:
    bus::Bus& bus_;
    std::string process_;
    std::string host_;
    int32_t pid_;
    int64_t mark_seq_ = 0;
    int64_t acked_ = 0;
};

}  // namespace gyrocal::testing
