#pragma once
// How a test reaches the node it drives, so one scenario serves the node in-process over memq://
// and the real process over UDP multicast:
//   pace()          after a burst of published messages: let the receiver keep up;
//   until(done, t)  dispatch until done() holds or t has passed (false: it did not).
// ForProcess: the test's own bus on the process's multicast port; ForNode: the node's own bus
// (memq://), its STATUS published on every round, since no heartbeat loop runs in-process.
#include <chrono>
#include <functional>
#include <thread>

#include "bus/bus.hpp"
#include "bus_wait.hpp"

namespace gyrocal::testing {

struct Wire {
    std::function<void()> pace;
    std::function<bool(const std::function<bool()>&, std::chrono::milliseconds)> until;
};

inline Wire ForProcess(Bus& bus) {
    return {[&bus] {
                bus.Handle(std::chrono::milliseconds(0));
                // Pacing, not a wait: ~100 msgs / 2 ms, what the process's socket buffer holds.
                std::this_thread::sleep_for(std::chrono::milliseconds(2));
            },
            [&bus](const std::function<bool()>& done, std::chrono::milliseconds limit) {
                return HandleUntil(bus, done, limit, std::chrono::milliseconds(20));
            }};
}

// Node: anything with bus() and PublishStatus() (the processors' node classes).
template <class Node>
Wire ForNode(Node& node) {
    auto drain = [&node] {
        for (int i = 0; i < 1000000 && node.bus().Handle(std::chrono::milliseconds(0)); ++i) {
        }
    };
    return {drain,
            [&node, drain](const std::function<bool()>& done, std::chrono::milliseconds limit) {
                const auto end = std::chrono::steady_clock::now() + limit;
                while (true) {
                    node.PublishStatus();
                    drain();
                    if (done()) return true;
                    if (std::chrono::steady_clock::now() >= end) return false;
                }
            }};
}

}  // namespace gyrocal::testing
