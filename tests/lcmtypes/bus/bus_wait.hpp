#pragma once
// Bounded waits on the bus for the tests that talk to real processes or nodes (no test waits
// forever on a message that was lost), and the messages they keep meanwhile.
#include <chrono>
#include <string>
#include <vector>

#include "lcmtypes/bus/bus.hpp"

namespace gyrocal::testing {

// Handles `bus` until `done()` holds or `timeout` passes; whether it holds. `step` bounds each
// wait for a message.
template <class Done>
bool HandleUntil(bus::Bus& bus, Done&& done, std::chrono::milliseconds timeout,
                 std::chrono::milliseconds step = std::chrono::milliseconds(50)) {
    const auto end = std::chrono::steady_clock::now() + timeout;
    while (!done()) {
        if (std::chrono::steady_clock::now() >= end) return false;
        bus.Handle(step);
    }
    return true;
}

// Keeps every Msg heard on `channel` (a name or a regex) in `into`, in arrival order; `into`
// must outlive the bus.
template <class Msg>
void CollectInto(bus::Bus& bus, const std::string& channel, std::vector<Msg>& into) {
    bus.Subscribe<Msg>(channel, [&into](const Msg& m, const std::string&) { into.push_back(m); });
}

}  // namespace gyrocal::testing
