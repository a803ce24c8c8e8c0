#pragma once
// Shared pieces of the multi-process recorder and replay tests: start a real gyrocal-recorder on a
// test's own multicast port and wait until it listens (rows are counted with scratch_db.hpp).
#include <chrono>
#include <string>
#include <vector>

#include "gyrocal/status_t.hpp"
#include "lcmtypes/bus/bus.hpp"
#include "lcmtypes/launch/child_process.hpp"
#include "tests/lcmtypes/bus/bus_wait.hpp"
#include "tests/store/scratch_db.hpp"

namespace gyrocal::testing {

inline std::string UrlForPort(int port) {
    return "udpm://239.255.76.67:" + std::to_string(port) + "?ttl=0&recv_buf_size=4194304";
}

inline launch::ChildProcess StartRecorder(const std::string& db, const std::string& url,
                                          std::vector<std::string> extra = {}) {
    std::vector<std::string> argv = {std::string(GYROCAL_BIN_DIR) + "/gyrocal-recorder", "--db", db,
                                     "--lcm-url", url};
    argv.insert(argv.end(), extra.begin(), extra.end());
    return launch::ChildProcess(argv, "", db + ".recorder.err");
}

// Waits (bounded) for a STATUS heartbeat of a recorder with `pid`: it then has subscribed.
inline bool WaitForRecorder(bus::Bus& bus, int pid, std::chrono::milliseconds timeout) {
    bool seen = false;
    bus.Subscribe<status_t>("STATUS", [&](const status_t& s, const std::string&) {
        if (s.process == "gyrocal-recorder" && s.pid == pid) seen = true;
    });
    return HandleUntil(
        bus, [&] { return seen; }, timeout);
}

// A real gyrocal-recorder writing `db`, and a bus on its `url` to publish to it and to hear it.
struct RecorderOnBus {
    RecorderOnBus(const std::string& db, const std::string& url,
                  std::vector<std::string> extra = {})
        : bus(bus::BusOptions{url}), rec(StartRecorder(db, url, std::move(extra))) {}
    // True once its STATUS is heard (within 10 s): it has subscribed by then.
    bool Listening() { return WaitForRecorder(bus, rec.pid(), std::chrono::seconds(10)); }
    bus::Bus bus;
    launch::ChildProcess rec;
};

}  // namespace gyrocal::testing
