#pragma once
// The recorder's store-and-forward (gyrocal-recorder --push-to URL): when a run ends on the bus,
// a separate `gyrocal push` process is started that waits until the run's stop is committed in
// the station file and then sends every run with something new to the central database. The
// recorder never waits on it: starting the process is all it does (posix_spawn, about a
// millisecond), and it reaps it later without blocking. The push failing (centre down, network
// out) costs the recorder nothing; the runs are sent by the next push, manual or at the next
// run's end, since the station records what was pushed.
//
// The URL reaches the push through its environment (GYROCAL_CENTRAL_URL), never its command
// line, so `ps` does not show it; put the password in a PGPASSFILE rather than in the URL.
#include <sys/types.h>

#include <string>
#include <vector>

namespace gyrocal::recorder::node {

class BackgroundPush {
public:
    // `gyrocal` is looked for beside this executable. `url` "" disables everything.
    BackgroundPush(std::string url, std::string db_path);
    bool enabled() const { return !url_.empty(); }

    // Called when a run's stop or abort is seen: a push is started at the next Poll().
    void RunEnded(const std::string& run_id);
    // Starts the pending pushes and reaps the finished ones (non-blocking). Returns log lines.
    std::vector<std::string> Poll();

private:
    std::string url_, db_path_, exe_;
    std::vector<std::string> pending_;
    std::vector<pid_t> running_;
};

}  // namespace gyrocal::recorder::node
