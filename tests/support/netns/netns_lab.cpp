#include "tests/support/netns/netns_lab.hpp"

#include <fcntl.h>
#include <sched.h>
#include <unistd.h>

#include <cstdlib>
#include <stdexcept>

namespace gyrocal::testing {
namespace {

int Shell(const std::string& command) {
    return std::system((command + " >/dev/null 2>&1").c_str());
}

}  // namespace

std::string NetnsLab::Unavailable() {
    if (geteuid() != 0)
        return "needs root to create network namespaces (ip netns); CI runs as root";
    const std::string probe = "gyrocal-probe-" + std::to_string(getpid());
    if (Shell("ip netns add " + probe) != 0)
        return "`ip netns add` failed here (no iproute2 or no CAP_SYS_ADMIN)";
    const bool veth =
        Shell("ip -n " + probe + " link add vprobe0 type veth peer name vprobe1") == 0;
    const bool bridge = Shell("ip -n " + probe + " link add br0 type bridge") == 0;
    Shell("ip netns delete " + probe);
    if (!veth) return "this kernel cannot create veth pairs inside a namespace";
    if (!bridge) return "this kernel cannot create a bridge inside a namespace";
    return "";
}

void NetnsLab::Run(const std::string& command) {
    if (Shell(command) != 0) throw std::runtime_error("netns lab: '" + command + "' failed");
}

NetnsLab::NetnsLab(const std::string& tag, int hosts, int net) {
    const std::string base = tag + "-" + std::to_string(getpid());
    switch_ = base + "-sw";
    try {
        Run("ip netns add " + switch_);
        created_.push_back(switch_);
        Run("ip -n " + switch_ + " link add br0 type bridge mcast_snooping 0");
        Run("ip -n " + switch_ + " link set br0 up");
        for (int k = 1; k <= hosts; ++k) {
            const std::string h = base + "-h" + std::to_string(k);
            const std::string port = "p" + std::to_string(k);
            Run("ip netns add " + h);
            created_.push_back(h);
            hosts_.push_back(h);
            Run("ip -n " + switch_ + " link add " + port + " type veth peer name eth0 netns " + h);
            Run("ip -n " + switch_ + " link set " + port + " master br0");
            Run("ip -n " + switch_ + " link set " + port + " up");
            Run("ip -n " + h + " link set lo up");
            Run("ip -n " + h + " addr add 10." + std::to_string(net) + ".0." + std::to_string(k) +
                "/24 dev eth0");
            Run("ip -n " + h + " link set eth0 up");
            Run("ip -n " + h + " route add 224.0.0.0/4 dev eth0");
        }
    } catch (...) {
        for (const auto& ns : created_) Shell("ip netns delete " + ns);
        throw;
    }
}

NetnsLab::~NetnsLab() {
    for (auto it = created_.rbegin(); it != created_.rend(); ++it) Shell("ip netns delete " + *it);
}

std::unique_ptr<launch::ChildProcess> NetnsLab::Start(int k, std::vector<std::string> argv,
                                                      const std::string& log) const {
    argv.insert(argv.begin(), {"ip", "netns", "exec", host(k)});
    return std::make_unique<launch::ChildProcess>(argv, log, log);
}

void NetnsLab::SetLink(int k, bool up) const {
    const std::string cmd =
        "ip -n " + switch_ + " link set p" + std::to_string(k) + (up ? " up" : " down");
    if (Shell(cmd) != 0) throw std::runtime_error("netns lab: '" + cmd + "' failed");
}

std::thread NetnsLab::OnHost(int k, std::function<void()> fn) const {
    const std::string path = "/run/netns/" + host(k);
    return std::thread([path, fn = std::move(fn)] {
        const int fd = open(path.c_str(), O_RDONLY | O_CLOEXEC);
        if (fd < 0 || setns(fd, CLONE_NEWNET) != 0)
            throw std::runtime_error("cannot enter " + path);
        close(fd);
        fn();
    });
}

}  // namespace gyrocal::testing
