#pragma once
// Bounded waits on the bus for the tests that talk to real processes or nodes: no test waits
// forever on a message that was lost.
#include <chrono>

#include "bus/bus.hpp"

namespace gyrocal::testing {

// Handles `bus` until `done()` holds or `timeout` passes; whether it holds. `step` bounds each
// wait for a message.
template <class Done>
bool HandleUntil(Bus& bus, Done&& done, std::chrono::milliseconds timeout,
                 std::chrono::milliseconds step = std::chrono::milliseconds(50)) {
    const auto end = std::chrono::steady_clock::now() + timeout;
    while (!done()) {
        if (std::chrono::steady_clock::now() >= end) return false;
        bus.Handle(step);
    }
    return true;
}

}  // namespace gyrocal::testing
