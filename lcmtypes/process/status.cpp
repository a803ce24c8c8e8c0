#include "lcmtypes/process/status.hpp"

#include <unistd.h>

#include <iostream>

#include "gyrocal/status_t.hpp"
#include "lcmtypes/channels/channels.hpp"
#include "lcmtypes/process/shutdown.hpp"

namespace gyrocal::process {

void RateLimitedLog::Warn(const std::string& key, const std::string& text) {
    auto now = std::chrono::steady_clock::now();
    Entry& e = entries_[key];
    if (e.last != std::chrono::steady_clock::time_point{} &&
        now - e.last < std::chrono::seconds(1)) {
        ++e.suppressed;
        return;
    }
    std::cerr << process_ << ": warning: " << text;
    if (e.suppressed > 0) std::cerr << " (" << e.suppressed << " more like it suppressed)";
    std::cerr << "\n";
    e.last = now;
    e.suppressed = 0;
}

std::string HostName() { return flow::ThisHost(); }

StatusReporter::StatusReporter(bus::Bus& bus, std::string process, std::chrono::milliseconds period)
    : bus_(bus),
      process_(std::move(process)),
      host_(HostName()),
      period_(period),
      log_(process_),
      acker_(bus, process_) {}

void StatusReporter::Reject(const std::string& reason_key, const std::string& detail) {
    ++rejected_;
    last_reject_ = reason_key + ": " + detail;
    log_.Warn(reason_key, last_reject_);
}

void StatusReporter::Tick() {
    acker_.Poll();
    if (std::chrono::steady_clock::now() - last_ >= period_) PublishNow();
}

void StatusReporter::PublishNow() {
    last_ = std::chrono::steady_clock::now();
    const bus::BusCounters& c = bus_.counters();
    status_t s;
    s.utime = bus::WallClockUtime();
    s.process = process_;
    s.host = host_;
    s.pid = static_cast<int32_t>(getpid());
    s.state = state_;
    s.received = c.received;
    s.published = c.published + 1;  // counts this heartbeat too
    s.decode_errors = c.decode_errors + decode_errors_;
    s.seq_gaps = c.seq_gaps + seq_gaps_;
    s.queue_drops = queue_drops_;
    s.rejected = rejected_;
    s.last_reject = !last_reject_.empty()            ? last_reject_
                    : !c.first_handler_error.empty() ? "handler_error: " + c.first_handler_error
                                                     : c.last_decode_error;
    std::map<std::string, double> extra = extra_;
    extra["seq_backwards"] = static_cast<double>(c.seq_backwards);
    extra["publish_errors"] = static_cast<double>(c.publish_errors);
    // Messages a handler failed on (each still given to the channel's other subscribers), in
    // all and per channel: a loss the data did not show.
    extra["handler_errors"] = static_cast<double>(c.handler_errors);
    for (const auto& [channel, n] : c.handler_errors_by_channel)
        extra["handler_errors:" + channel] = static_cast<double>(n);
    for (const auto& [name, value] : extra) {
        s.extra_names.push_back(name);
        s.extra_values.push_back(value);
    }
    s.num_extra = static_cast<int16_t>(s.extra_names.size());
    bus_.Publish(std::string(channels::kStatus), s);
}

void RunLoop(bus::Bus& bus, StatusReporter& status, const std::function<bool()>& done,
             std::chrono::milliseconds poll) {
    if (status.state() == "starting") status.set_state("running");
    status.PublishNow();
    while (!StopRequested() && !(done && done())) {
        try {
            bus.Handle(poll);
        } catch (...) {
            // A handler failed: the process stops with it (process_main prints it), after a last
            // heartbeat that counts it (handler_errors) and says what it was (last_reject).
            status.set_state("failed");
            status.PublishNow();
            throw;
        }
        status.Tick();
    }
    status.PublishNow();
    status.acker().Leave();
}

}  // namespace gyrocal::process
