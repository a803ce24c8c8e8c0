#pragma once
// A child OS process started by argv (no shell), for the calibrate launcher and for tests that
// run the real processes. The child gets its own process group (so a terminal's Ctrl-C reaches
// only the parent, which stops children in order) and dies with its parent (PR_SET_PDEATHSIG).
// The destructor stops a still-running child: SIGTERM, then SIGKILL after a grace period, so a
// failing test never leaves processes behind.
#include <sys/types.h>

#include <chrono>
#include <optional>
#include <string>
#include <vector>

namespace gyrocal::launch {

struct ExitStatus {
    bool exited = false;  // true: normal exit with code; false: killed by signal
    int code = 0;         // exit code when exited
    int signal = 0;       // signal number when killed
    std::string Describe() const;
};

// Where a child's output goes and where it runs.
struct ChildOptions {
    std::string stdout_path;  // "" = inherit
    std::string stderr_path;  // "" = inherit; the same path as stdout_path = one combined log
    std::string working_dir;  // "" = the parent's
    // The parent's fds that become the child's 3, 4, ... in this order (e.g. the ends of the
    // pipes a browser's --remote-debugging-pipe talks over). When not empty, every other fd above
    // 2 is closed in the child, so it holds nothing else of the parent's.
    std::vector<int> child_fds;
};

class ChildProcess {
public:
    // Starts argv[0] (searched in PATH when it has no '/'). stdout/stderr go to the given
    // files when not empty ("" = inherit; the same path for both = one combined log).
    // Throws std::runtime_error, with the reason, when it cannot start.
    explicit ChildProcess(std::vector<std::string> argv, const std::string& stdout_path = "",
                          const std::string& stderr_path = "");
    // The same with every option; a working directory that cannot be entered is a start failure
    // (std::runtime_error naming the directory and the reason).
    ChildProcess(std::vector<std::string> argv, const ChildOptions& options);
    ChildProcess(const ChildProcess&) = delete;
    ChildProcess& operator=(const ChildProcess&) = delete;
    ChildProcess(ChildProcess&& other) noexcept;
    ~ChildProcess();

    pid_t pid() const { return pid_; }
    const std::string& name() const { return name_; }
    void Signal(int sig);  // to the child's process group (it leads one)
    // Non-blocking check; returns the status once the child has ended.
    std::optional<ExitStatus> Poll();
    // Waits up to `timeout`; nullopt when still running.
    std::optional<ExitStatus> Wait(std::chrono::milliseconds timeout);
    // Waits as long as the child runs and returns how it ended.
    ExitStatus Wait();
    // SIGTERM, wait up to `grace`, then SIGKILL; returns how it ended.
    ExitStatus Stop(std::chrono::milliseconds grace = std::chrono::milliseconds(3000));

private:
    pid_t pid_ = -1;
    std::string name_;
    std::optional<ExitStatus> status_;
};

// Full path of `program` found in $PATH (an empty entry is the current directory), or `program`
// itself when it contains a '/'; "" when it is not there or not executable. The one PATH search
// of the project: what execvp would start, checked before starting it.
std::string FindOnPath(const std::string& program);

// The whole text of a file, "" when it cannot be read: what a child wrote to its log.
std::string ReadLog(const std::string& path);

}  // namespace gyrocal::launch
