#include "lcmtypes/process/shutdown.hpp"

#include <atomic>
#include <csignal>

namespace gyrocal::process {
namespace {
std::atomic<bool> g_stop{false};
extern "C" void OnStopSignal(int) { g_stop.store(true); }
}  // namespace

void InstallStopHandlers() {
    struct sigaction sa {};
    sa.sa_handler = OnStopSignal;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, nullptr);
    sigaction(SIGTERM, &sa, nullptr);
}

bool StopRequested() { return g_stop.load(); }
void RequestStop() { g_stop.store(true); }

}  // namespace gyrocal::process
