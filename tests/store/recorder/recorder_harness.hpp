#pragma once
// Shared pieces of the multi-process recorder tests: start a real gyrocal-recorder on a test's
// own multicast port, wait until it listens, and count rows in its database.
#include <chrono>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include "bus/bus.hpp"
#include "gyrocal/status_t.hpp"
#include "launch/child_process.hpp"
#include "sqlite_db.hpp"

namespace gyrocal::testing {

inline std::string UrlForPort(int port) {
    return "udpm://239.255.76.67:" + std::to_string(port) + "?ttl=0&recv_buf_size=4194304";
}

inline std::string TempPath(const std::string& name) {
    const auto dir = std::filesystem::temp_directory_path() / "gyrocal_store_tests";
    std::filesystem::create_directories(dir);
    const auto p = dir / (name + "_" + std::to_string(::getpid()));
    for (const char* ext : {"", "-wal", "-shm"}) std::filesystem::remove(p.string() + ext);
    return p.string();
}

inline ChildProcess StartRecorder(const std::string& db, const std::string& url,
                                  std::vector<std::string> extra = {}) {
    std::vector<std::string> argv = {std::string(GYROCAL_BIN_DIR) + "/gyrocal-recorder", "--db",
                                     db, "--lcm-url", url};
    argv.insert(argv.end(), extra.begin(), extra.end());
    return ChildProcess(argv, "", db + ".recorder.err");
}

// Waits (bounded) for a STATUS heartbeat of a recorder with `pid`: it then has subscribed.
inline bool WaitForRecorder(Bus& bus, int pid, std::chrono::milliseconds timeout) {
    bool seen = false;
    bus.Subscribe<status_t>("STATUS", [&](const status_t& s, const std::string&) {
        if (s.process == "gyrocal-recorder" && s.pid == pid) seen = true;
    });
    const auto end = std::chrono::steady_clock::now() + timeout;
    while (!seen && std::chrono::steady_clock::now() < end) bus.Handle(std::chrono::milliseconds(50));
    return seen;
}

inline int64_t Count(const std::string& db_path, const std::string& sql) {
    store::Db db(db_path, store::Db::Mode::kReadOnly);
    store::Stmt s(db, sql);
    return s.Step() ? s.Int(0) : -1;
}

// Polls `sql` until it returns `expected` or `timeout` passes; returns the last value.
inline int64_t WaitForCount(const std::string& db_path, const std::string& sql, int64_t expected,
                            std::chrono::milliseconds timeout) {
    const auto end = std::chrono::steady_clock::now() + timeout;
    int64_t n = -1;
    for (;;) {
        try {
            n = Count(db_path, sql);
        } catch (const std::exception&) {
            n = -1;  // not created yet
        }
        if (n == expected || std::chrono::steady_clock::now() >= end) return n;
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
}

}  // namespace gyrocal::testing
