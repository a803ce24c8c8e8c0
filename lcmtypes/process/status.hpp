#pragma once
// The STATUS heartbeat every process publishes once a second (wall clock: it is about the
// process, not the data), and the rate-limited stderr warnings that go with refusals. Every
// process with a heartbeat also answers the flow marks of non-real-time sources (flow/), so a
// source paces on it: the heartbeat says it is there, the answers say how far it has come.
#include <chrono>
#include <cstdint>
#include <exception>
#include <functional>
#include <map>
#include <string>

#include "lcmtypes/bus/bus.hpp"
#include "lcmtypes/flow/flow_acker.hpp"

namespace gyrocal::process {

// Prints a warning at most once per second per key, then says how many were suppressed.
class RateLimitedLog {
public:
    explicit RateLimitedLog(std::string process) : process_(std::move(process)) {}
    void Warn(const std::string& key, const std::string& text);

private:
    struct Entry {
        std::chrono::steady_clock::time_point last{};
        int64_t suppressed = 0;
    };
    std::string process_;
    std::map<std::string, Entry> entries_;
};

class StatusReporter {
public:
    StatusReporter(bus::Bus& bus, std::string process,
                   std::chrono::milliseconds period = std::chrono::milliseconds(1000));

    void set_state(std::string state) { state_ = std::move(state); }
    const std::string& state() const { return state_; }
    // A decoded message refused by a guard: counted, reason kept for STATUS, warned (rate-limited).
    void Reject(const std::string& reason_key, const std::string& detail);
    // Runs a handler's body: an exception it throws is a counted refusal ("internal_error") of
    // that message, never thrown through LCM's C stack.
    template <class F>
    void Guarded(F&& body) {
        try {
            body();
        } catch (const std::exception& e) {
            Reject("internal_error", e.what());
        }
    }
    void AddQueueDrops(int64_t n) { queue_drops_ += n; }
    // Loss a process finds itself beyond its bus's typed subscriptions (the recorder decodes raw
    // bytes): added to the bus's own counts in STATUS.
    void AddSeqGaps(int64_t n) { seq_gaps_ += n; }
    void AddDecodeErrors(int64_t n) { decode_errors_ += n; }
    void SetExtra(const std::string& name, double value) { extra_[name] = value; }
    int64_t rejected() const { return rejected_; }
    // The flow-mark answers of this process (a node whose handling ends later than its handler
    // sets a gate on it: the recorder).
    flow::FlowAcker& acker() { return acker_; }

    void Tick();        // publishes when the period has elapsed; answers held flow marks
    void PublishNow();  // e.g. on state changes and just before exit

private:
    bus::Bus& bus_;
    std::string process_;
    std::string host_;
    std::chrono::milliseconds period_;
    std::chrono::steady_clock::time_point last_{};
    std::string state_ = "starting";
    int64_t rejected_ = 0;
    int64_t queue_drops_ = 0;
    int64_t seq_gaps_ = 0;
    int64_t decode_errors_ = 0;
    std::string last_reject_;
    std::map<std::string, double> extra_;
    RateLimitedLog log_;
    flow::FlowAcker acker_;
};

// The loop every node runs: dispatch messages, heartbeat, until SIGINT/SIGTERM or done(); at
// the end, the last heartbeat and the last flow answers (no source waits for it any more).
void RunLoop(bus::Bus& bus, StatusReporter& status, const std::function<bool()>& done = {},
             std::chrono::milliseconds poll = std::chrono::milliseconds(50));

std::string HostName();

}  // namespace gyrocal::process
