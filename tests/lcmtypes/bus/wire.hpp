#pragma once
// How a test reaches the node it drives, so one scenario serves the node in-process over memq://
// and the real process over UDP multicast:
//   pace()          after a burst of published messages: let the receiver keep up;
//   until(done, t)  dispatch until done() holds or t has passed (false: it did not).
// ForProcess: the test's own bus on the process's multicast port, paced on the process's answers
// to flow marks (flow_pacer.hpp); ForNode: the node's own bus (memq://), its STATUS published on
// every round, since no heartbeat loop runs in-process.
#include <gtest/gtest.h>

#include <chrono>
#include <functional>
#include <memory>
#include <string>

#include "lcmtypes/bus/bus.hpp"
#include "tests/lcmtypes/bus/bus_wait.hpp"
#include "tests/lcmtypes/bus/flow_pacer.hpp"

namespace gyrocal::testing {

struct Wire {
    std::function<void()> pace;
    std::function<bool(const std::function<bool()>&, std::chrono::milliseconds)> until;
};

// `process`: the process's STATUS name, whose answers to the marks pace the test.
inline Wire ForProcess(bus::Bus& bus, const std::string& process) {
    auto pacer = std::make_shared<FlowPacer>(bus, process);
    return {[pacer] { EXPECT_TRUE(pacer->Sync()) << "the process answered no flow mark"; },
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
