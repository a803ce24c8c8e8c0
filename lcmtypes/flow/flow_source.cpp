#include "lcmtypes/flow/flow_source.hpp"

#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>

#include "gyrocal/flow_ack_t.hpp"
#include "gyrocal/flow_mark_t.hpp"
#include "gyrocal/status_t.hpp"
#include "lcmtypes/channels/channels.hpp"
#include "lcmtypes/flow/flow_acker.hpp"

namespace gyrocal::flow {

namespace {
using Clock = std::chrono::steady_clock;

}  // namespace

FlowSource::FlowSource(bus::Bus& bus, std::string process, WindowOptions options)
    : bus_(bus), self_(std::move(process)), options_(options), window_(options) {
    bus_.Subscribe<flow_ack_t>(std::string(channels::kFlowAck),
                               [this](const flow_ack_t& a, const std::string&) {
                                   if (!self_.Is(a.source_host, a.source_pid))
                                       return;  // another source's
                                   const ConsumerId id{a.host, a.pid};
                                   if (a.leaving) {
                                       window_.OnLeave(id);
                                       return;
                                   }
                                   const size_t before = window_.paced_consumers();
                                   window_.OnAck(id, a.process, a.mark_seq, Clock::now());
                                   any_ack_ = true;
                                   if (window_.paced_consumers() != before)
                                       last_new_consumer_ = Clock::now();
                               });
    bus_.Subscribe<status_t>(std::string(channels::kStatus),
                             [this](const status_t& s, const std::string&) {
                                 if (self_.Is(s.host, s.pid)) return;  // itself
                                 // A heartbeat from the past is a replay (a log, a stored run),
                                 // not a process: 30 s covers clocks of hosts on one LAN.
                                 if (std::abs(s.utime - bus::WallClockUtime()) > 30'000'000) return;
                                 window_.OnHeartbeat({s.host, s.pid}, s.process, Clock::now());
                             });
    seen_published_ = bus_.counters().published;
    seen_bytes_ = bus_.counters().published_bytes;
}

void FlowSource::PublishMark(int64_t data_utime) {
    const Mark m = window_.IssueMark(Clock::now());
    flow_mark_t f = self_.Message<flow_mark_t>();
    f.mark_seq = m.mark_seq;
    f.published = bus_.counters().published;
    f.data_utime = data_utime;
    bus_.Publish(std::string(channels::kFlowMark), f);
}

void FlowSource::Discover(std::chrono::milliseconds limit) {
    discovered_ = true;
    Sync(data_utime_);
    const auto start = Clock::now();
    while (Clock::now() - start < limit) {
        bus_.Handle(std::chrono::milliseconds(10));
        if (any_ack_ && Clock::now() - last_new_consumer_ > std::chrono::milliseconds(200)) break;
        // A running consumer answers within milliseconds; nobody in half a second: nobody.
        if (!any_ack_ && Clock::now() - start > std::chrono::milliseconds(500)) break;
        if (window_.MarkDue(Clock::now())) PublishMark(data_utime_);
    }
}

void FlowSource::Sync(int64_t data_utime) {
    data_utime_ = data_utime;
    const bus::BusCounters& c = bus_.counters();
    window_.OnPublished(c.published - seen_published_, c.published_bytes - seen_bytes_);
    seen_published_ = c.published;
    seen_bytes_ = c.published_bytes;
    if (window_.MarkDue(Clock::now())) {
        PublishMark(data_utime);
        seen_published_ = bus_.counters().published;  // the mark itself is not data to pace
        seen_bytes_ = bus_.counters().published_bytes;
    }
}

std::optional<int64_t> FlowSource::Credit() {
    const std::optional<int64_t> credit = window_.Credit(Clock::now());
    for (const FlowEvent& e : window_.TakeEvents()) reports_.push_back(e.text);
    return credit;
}

void FlowSource::WaitForCredit(std::chrono::milliseconds max_wait) {
    const auto start = Clock::now();
    while (Clock::now() - start < max_wait) {
        bus_.Handle(std::chrono::milliseconds(1));
        Sync(data_utime_);  // a fresh mark while waiting, for a consumer that joined late
        const auto credit = Credit();
        if (!credit || *credit > 0) break;
        ForgetEndedProcesses();
    }
    waited_s_ += std::chrono::duration<double>(Clock::now() - start).count();
}

void FlowSource::ForgetEndedProcesses() {
    // A consumer on this host that was killed (SIGKILL sends no last answer) need not be waited
    // for until its timeout: the kernel knows it is gone. Checked at most every 200 ms.
    if (Clock::now() - last_alive_check_ < std::chrono::milliseconds(200)) return;
    last_alive_check_ = Clock::now();
    for (const ConsumerId& id : window_.Behind()) {
        if (id.host != self_.host) continue;  // another host: only its timeout tells
        if (kill(id.pid, 0) != 0 && errno == ESRCH) window_.OnGone(id);
    }
}

bool FlowSource::Drain(int64_t data_utime) {
    Sync(data_utime);
    PublishMark(data_utime);
    seen_published_ = bus_.counters().published;
    seen_bytes_ = bus_.counters().published_bytes;
    const int64_t last = window_.marks_issued();
    const auto start = Clock::now();
    // Every consumer answers the last mark, or drops out at its timeout (Credit expires it).
    while (!window_.AllAcked(last)) {
        bus_.Handle(std::chrono::milliseconds(5));
        Credit();
        ForgetEndedProcesses();
        if (std::chrono::duration<double>(Clock::now() - start).count() >
            options_.consumer_timeout_s + 1.0)
            break;
    }
    return window_.AllAcked(last) && window_.dropped_total() == 0;
}

std::vector<std::pair<std::string, double>> FlowSource::Extras() const {
    return {{"flow_consumers", static_cast<double>(window_.paced_consumers())},
            {"flow_wait_s", waited_s_},
            {"flow_marks", static_cast<double>(window_.marks_issued())},
            {"flow_dropped", static_cast<double>(window_.dropped_total())},
            {"flow_window_bytes", static_cast<double>(options_.window_bytes)}};
}

std::vector<std::string> FlowSource::TakeReports() {
    std::vector<std::string> out;
    out.swap(reports_);
    return out;
}

}  // namespace gyrocal::flow
