#pragma once
// A lab of several hosts on one machine, for tests: each host is a network namespace with its own
// loopback and one interface (eth0, 10.<net>.0.<k>/24) cabled by a veth pair to a port (p<k>) of
// a bridge that lives in a namespace of its own (the "switch"), so nothing can reach the
// machine's real interfaces. Multicast is routed out of eth0 in each host (224.0.0.0/4) and the
// bridge floods it (IGMP snooping off: no querier here). LCM inside uses ttl=1.
//
// Every namespace name carries the test's tag and pid, so concurrent test runs never meet; the
// destructor deletes them all (and with them the veth pairs), also when a test fails.
// Needs root: NetnsLab::Unavailable() says why it cannot be built here (for GTEST_SKIP).
#include <chrono>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "lcmtypes/launch/child_process.hpp"

namespace gyrocal::testing {

class NetnsLab {
public:
    // "" when a lab can be built here, else the reason (not root, no `ip netns`, no veth...).
    static std::string Unavailable();

    // Builds `hosts` hosts named "<tag>-h1".."<tag>-hN" (tag gets the pid appended). `net` picks
    // the 10.<net>.0.0/24 subnet so that labs of concurrent tests differ. Throws
    // std::runtime_error naming the command that failed (everything built so far is removed).
    NetnsLab(const std::string& tag, int hosts, int net);
    ~NetnsLab();
    NetnsLab(const NetnsLab&) = delete;
    NetnsLab& operator=(const NetnsLab&) = delete;

    const std::string& host(int k) const {
        return hosts_.at(static_cast<size_t>(k - 1));
    }  // 1-based
    // Starts argv inside host k (ip netns exec), logs as ChildProcess does.
    std::unique_ptr<launch::ChildProcess> Start(int k, std::vector<std::string> argv,
                                                const std::string& log) const;
    // The switch port of host k down (its cable pulled: the host keeps its address and routes,
    // its packets go nowhere) or up again.
    void SetLink(int k, bool up) const;
    // Runs fn on a new thread whose network namespace is host k's: sockets it opens (an LCM bus)
    // are that host's.
    std::thread OnHost(int k, std::function<void()> fn) const;

private:
    void Run(const std::string& command);  // throws naming the command
    std::string switch_;
    std::vector<std::string> hosts_;
    std::vector<std::string> created_;  // namespaces to delete
};

}  // namespace gyrocal::testing
