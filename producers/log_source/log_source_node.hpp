#pragma once
// gyrocal-log-source: an LCM log (lcm-logger's file) published back onto the bus, every event on
// its channel with its bytes unchanged, paced by its recorded time (--speed X: X recorded seconds
// per wall second) or as fast as every consumer keeps up (--max: flow control, lcmtypes/flow),
// which lcm-logplayer cannot do. The file is checked whole first (event headers and lengths), so
// a damaged log publishes nothing. The flow control of the recorded run (FLOW_MARK, FLOW_ACK) is
// not replayed.
//
// Threads: one. Run() is RunLoop with a zero poll; each turn publishes the events that are due
// (or that the consumers have room for), then sleeps until the next is due or waits for their
// answers (at most 20 ms). It ends after the last event, once every consumer has answered the
// last mark (--max), or after --drain-s.
#include <chrono>
#include <cstdint>
#include <fstream>
#include <memory>
#include <optional>
#include <regex>
#include <string>

#include "lcmtypes/bus/bus.hpp"
#include "lcmtypes/flow/flow_source.hpp"
#include "lcmtypes/process/flow_options.hpp"
#include "lcmtypes/process/status.hpp"
#include "producers/log_source/lcm_log.hpp"

namespace gyrocal::log_source {

struct LogSourceOptions {
    std::string file;
    std::string lcm_url;
    double speed = 1.0;           // [recorded s / wall s]
    bool max = false;             // as fast as the consumers keep up
    std::string channels = ".*";  // regex (ECMAScript, whole name) of the channels to publish
    double drain_s = 0.5;         // [s] after the last event, without consumers answering
    process::SourceFlowOptions flow = process::SourceFlowOptions::Defaults();
    static LogSourceOptions Defaults() { return {}; }
    std::string Validate() const;  // "" or one line naming the option and what is valid
};

// The first pass: every event header of the file read and its data skipped. Returns the number
// of events; throws log_source::LogError naming the offset of the first damage.
int64_t CheckLog(const std::string& file);

class LogSourceNode {
public:
    // Throws std::runtime_error when the file cannot be opened, BusError when LCM cannot.
    explicit LogSourceNode(const LogSourceOptions& options, int64_t events);
    // 0 when done or stopped, 1 when publishing failed or the file changed under it.
    int Run();
    // The node's bus: tests subscribe to it over memq:// (Handle it after Run() for the last
    // messages).
    bus::Bus& bus() { return bus_; }
    int64_t published() const { return published_; }

private:
    using Clock = std::chrono::steady_clock;
    bool Step();  // true when finished
    void Publish(const log_source::Event& e);
    void Fetch();  // the next event to publish (skipping filtered channels) into next_

    LogSourceOptions options_;
    std::regex channels_;
    std::ifstream in_;
    log_source::LogReader reader_;
    bus::Bus bus_;
    process::StatusReporter status_;
    std::unique_ptr<flow::FlowSource> flow_;
    std::optional<log_source::Event> next_;
    int64_t events_total_ = 0, published_ = 0, skipped_ = 0;
    int64_t first_utime_ = -1, last_utime_ = 0;
    bool started_ = false;
    Clock::time_point start_{}, finished_{};
    std::string error_;
};

}  // namespace gyrocal::log_source
