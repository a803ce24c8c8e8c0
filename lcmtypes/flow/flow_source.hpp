#pragma once
// The source side of flow control on a bus (flow_window.hpp says why and how): publishes the
// marks, hears the acks (FLOW_ACK) and the heartbeats (STATUS) and says how much the source may
// publish now. Used by every non-real-time source: the simulated rig, the CSV and line sources,
// the LCM log source and the replay of a stored run.
//
// A source publishes through its own Bus as before and calls Sync() after publishing (it reads
// the bus's own counters, so every datagram counts: samples, batches, STATUS, the marks
// themselves), then asks Credit(): <= 0 means wait (WaitForCredit dispatches the bus, so acks
// arrive and heartbeats and commands are served), nullopt means nobody is paced on (the source
// falls back to its own rate cap). At the end of its data it calls Drain(): a last mark, and
// every consumer must have handled it (bounded by the consumer timeout), so that "the source is
// done" means "every consumer has everything".
#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "lcmtypes/bus/bus.hpp"
#include "lcmtypes/flow/flow_acker.hpp"
#include "lcmtypes/flow/flow_window.hpp"

namespace gyrocal::flow {

class FlowSource {
public:
    FlowSource(bus::Bus& bus, std::string process, WindowOptions options);

    // Hears who is there before the first data: a first mark, then the bus dispatched until
    // the acks settle (200 ms without a new consumer after the first ack), no ack came in
    // 500 ms, or `limit` passes.
    void Discover(std::chrono::milliseconds limit = std::chrono::milliseconds(2000));
    bool discovered() const { return discovered_; }
    // Accounts what the bus published since the last call; publishes a mark when one is due.
    // `data_utime` [us]: data time of the newest message published (carried by the mark).
    void Sync(int64_t data_utime);
    // [B] may be published now; <= 0: wait; nullopt: no consumer to pace on.
    std::optional<int64_t> Credit();
    // Dispatches the bus for up to `max_wait`, returning early once there is credit again.
    void WaitForCredit(std::chrono::milliseconds max_wait);
    // The end of the data: a last mark, then waits until every paced consumer has answered it or
    // dropped out (consumer timeout). True when every one answered.
    bool Drain(int64_t data_utime);

    // STATUS counters: flow_consumers, flow_wait_s, flow_marks, flow_dropped, flow_window_bytes.
    std::vector<std::pair<std::string, double>> Extras() const;
    // Lines to print (a consumer dropped or admitted again), each once.
    std::vector<std::string> TakeReports();
    std::string Slowest() const { return window_.Slowest(); }
    double waited_s() const { return waited_s_; }
    size_t paced_consumers() const { return window_.paced_consumers(); }

private:
    void PublishMark(int64_t data_utime);
    void ForgetEndedProcesses();  // consumers on this host whose process is gone

    bus::Bus& bus_;
    Sender self_;
    WindowOptions options_;
    FlowWindow window_;
    int64_t seen_published_ = 0;
    int64_t seen_bytes_ = 0;
    int64_t data_utime_ = 0;
    double waited_s_ = 0;  // [s] wall time spent waiting for credit
    std::chrono::steady_clock::time_point last_new_consumer_{};
    std::chrono::steady_clock::time_point last_alive_check_{};
    bool any_ack_ = false;
    bool discovered_ = false;
    std::vector<std::string> reports_;
};

}  // namespace gyrocal::flow
