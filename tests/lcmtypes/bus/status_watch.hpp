#pragma once
// The STATUS heartbeat of one process as its process test watches it: the newest message, the
// named extras the process adds (per-sensor state, counters), and a bounded wait on them whose
// failure says where the counters stood.
#include <gtest/gtest.h>

#include <chrono>
#include <string>

#include "bus/bus.hpp"
#include "bus/channels.hpp"
#include "bus_wait.hpp"
#include "gyrocal/status_t.hpp"

namespace gyrocal::testing {

// Subscribes on construction, so build it before the process starts; it must not move (the
// handler holds `this`).
class StatusWatch {
public:
    StatusWatch(Bus& bus, std::string process) : process_(std::move(process)) {
        bus.Subscribe<status_t>(std::string(channels::kStatus),
                                [this](const status_t& m, const std::string&) {
                                    if (m.process != process_) return;
                                    last = m;
                                    seen = true;
                                });
    }
    StatusWatch(const StatusWatch&) = delete;
    StatusWatch& operator=(const StatusWatch&) = delete;

    // The extra named `name`; -1 (no state or count is negative) until the process reports it.
    double Extra(const std::string& name) const {
        for (int i = 0; i < last.num_extra; ++i)
            if (last.extra_names[i] == name) return last.extra_values[i];
        return -1.0;
    }

    status_t last{};
    bool seen = false;

private:
    std::string process_;
};

// Handles `bus` until `done()` holds; on timeout the failure carries the newest counters.
template <class Done>
::testing::AssertionResult StatusReaches(Bus& bus, const StatusWatch& watch, Done&& done,
                                         std::chrono::milliseconds timeout) {
    if (HandleUntil(bus, done, timeout, std::chrono::milliseconds(20)))
        return ::testing::AssertionSuccess();
    return ::testing::AssertionFailure()
           << "decode_errors " << watch.last.decode_errors << " rejected " << watch.last.rejected
           << " last_reject " << watch.last.last_reject;
}

}  // namespace gyrocal::testing
