#pragma once
// The STATUS heartbeat of one process as its tests watch it: the newest message and the named
// extras the process adds (per-sensor state, counters). Wait on it through wire.hpp.
#include <gtest/gtest.h>

#include <chrono>
#include <string>

#include "gyrocal/status_t.hpp"
#include "lcmtypes/bus/bus.hpp"
#include "lcmtypes/channels/channels.hpp"
#include "tests/lcmtypes/bus/bus_wait.hpp"

namespace gyrocal::testing {

// Subscribes on construction, so build it before the process starts; it must not move (the
// handler holds `this`).
class StatusWatch {
public:
    StatusWatch(bus::Bus& bus, std::string process) : process_(std::move(process)) {
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

}  // namespace gyrocal::testing
