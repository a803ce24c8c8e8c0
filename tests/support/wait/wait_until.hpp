#pragma once
// A bounded wait on a condition outside any bus (a file, a database, a log, another thread's
// flag), for every test: it says what it waits for and gives up after `timeout`, never a fixed
// sleep that a loaded machine outruns. (A condition on the bus: HandleUntil, bus_wait.hpp.)
#include <chrono>
#include <thread>

namespace gyrocal::testing {

// Checks `done()` every `poll` until it holds or `timeout` has passed; whether it held. The one
// sleep here is the poll interval: how late the wait sees the condition, not what it waits for.
template <class Done>
bool WaitUntil(Done&& done, std::chrono::milliseconds timeout,
               std::chrono::milliseconds poll = std::chrono::milliseconds(10)) {
    const auto end = std::chrono::steady_clock::now() + timeout;
    while (!done()) {
        if (std::chrono::steady_clock::now() >= end) return false;
        std::this_thread::sleep_for(poll);
    }
    return true;
}

}  // namespace gyrocal::testing
