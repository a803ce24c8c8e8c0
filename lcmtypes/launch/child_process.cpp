#include "lcmtypes/launch/child_process.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <thread>

namespace gyrocal::launch {

namespace {
// What the child reports through the close-on-exec pipe when it cannot start.
constexpr int kStepChdir = 1, kStepExec = 2;

ExitStatus FromWaitStatus(int st) {
    ExitStatus s;
    s.exited = WIFEXITED(st);
    s.code = s.exited ? WEXITSTATUS(st) : 0;
    s.signal = WIFSIGNALED(st) ? WTERMSIG(st) : 0;
    return s;
}
}  // namespace

std::string ReadLog(const std::string& path) {
    std::ifstream f(path);
    std::stringstream ss;
    ss << f.rdbuf();
    return ss.str();
}

std::string ExitStatus::Describe() const {
    if (exited) return "exit code " + std::to_string(code);
    return std::string("killed by signal ") + std::to_string(signal) + " (" + strsignal(signal) +
           ")";
}

std::string FindOnPath(const std::string& program) {
    if (program.find('/') != std::string::npos)
        return ::access(program.c_str(), X_OK) == 0 ? program : "";
    const char* path = std::getenv("PATH");
    const std::string dirs = path ? path : "";
    size_t start = 0;
    while (start <= dirs.size()) {
        const size_t end = std::min(dirs.find(':', start), dirs.size());
        const std::string dir = dirs.substr(start, end - start);
        const std::string candidate = (dir.empty() ? std::string(".") : dir) + "/" + program;
        if (::access(candidate.c_str(), X_OK) == 0) return candidate;
        start = end + 1;
    }
    return "";
}

ChildProcess::ChildProcess(std::vector<std::string> argv, const std::string& stdout_path,
                           const std::string& stderr_path)
    : ChildProcess(std::move(argv), ChildOptions{stdout_path, stderr_path, "", {}}) {}

ChildProcess::ChildProcess(std::vector<std::string> argv, const ChildOptions& options) {
    const std::string& stdout_path = options.stdout_path;
    const std::string& stderr_path = options.stderr_path;
    if (argv.empty()) throw std::invalid_argument("ChildProcess: empty argv");
    name_ = argv[0];
    std::vector<char*> cargv;
    for (auto& a : argv) cargv.push_back(a.data());
    cargv.push_back(nullptr);
    // A close-on-exec pipe tells the parent whether exec succeeded (it closes empty) or not
    // (the child writes which step failed and its errno).
    const int n_child_fds = static_cast<int>(options.child_fds.size());
    std::vector<int> high_fds(options.child_fds.size(), -1);  // allocated before the fork
    int fds[2];
    if (pipe2(fds, O_CLOEXEC) != 0)
        throw std::runtime_error("cannot start '" + name_ + "': pipe failed");
    const pid_t pid = fork();
    if (pid < 0) {
        close(fds[0]);
        close(fds[1]);
        throw std::runtime_error("cannot start '" + name_ +
                                 "': fork failed: " + std::strerror(errno));
    }
    if (pid == 0) {
        // Own process group: a terminal's Ctrl-C reaches only the launcher, which stops the
        // children in order. PDEATHSIG: children never outlive a launcher that was killed.
        setpgid(0, 0);
        prctl(PR_SET_PDEATHSIG, SIGTERM);
        if (!stdout_path.empty()) {
            int fd = open(stdout_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
            if (fd >= 0) dup2(fd, 1);
        }
        if (!stderr_path.empty()) {
            int fd = stderr_path == stdout_path
                         ? 1
                         : open(stderr_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
            if (fd >= 0) dup2(fd, 2);
        }
        int report_fd = fds[1];
        if (n_child_fds > 0) {
            // Out of the way first (above 2 + n), so that no dup2 below lands on a source.
            const int above = 3 + n_child_fds;
            report_fd = fcntl(fds[1], F_DUPFD_CLOEXEC, above);
            for (int i = 0; i < n_child_fds; ++i)
                high_fds[i] = fcntl(options.child_fds[i], F_DUPFD, above);
            for (int i = 0; i < n_child_fds; ++i) dup2(high_fds[i], 3 + i);
            for (int fd = above; fd < 256; ++fd)
                if (fd != report_fd) close(fd);
        }
        int failure[2] = {kStepChdir, 0};
        if (options.working_dir.empty() || chdir(options.working_dir.c_str()) == 0) {
            execvp(cargv[0], cargv.data());
            failure[0] = kStepExec;
        }
        failure[1] = errno;
        (void)!write(report_fd, failure, sizeof failure);
        _exit(127);
    }
    setpgid(pid, pid);  // also here: no race with a signal sent right after the start
    close(fds[1]);
    int failure[2] = {0, 0};
    const ssize_t n = read(fds[0], failure, sizeof failure);
    close(fds[0]);
    pid_ = pid;
    if (n == static_cast<ssize_t>(sizeof failure)) {
        Wait(std::chrono::milliseconds(1000));
        pid_ = -1;
        const std::string where = failure[0] == kStepChdir
                                      ? "cannot enter directory '" + options.working_dir + "': "
                                      : "";
        throw std::runtime_error("cannot start '" + name_ + "': " + where +
                                 std::strerror(failure[1]));
    }
}

ChildProcess::ChildProcess(ChildProcess&& other) noexcept
    : pid_(other.pid_), name_(std::move(other.name_)), status_(other.status_) {
    other.pid_ = -1;
}

ChildProcess::~ChildProcess() {
    if (pid_ > 0 && !status_) Stop(std::chrono::milliseconds(2000));
}

void ChildProcess::Signal(int sig) {
    // The whole process group: a child's own children (e.g. xvfb-run's Xvfb and java) go too.
    if (pid_ > 0 && !status_ && ::kill(-pid_, sig) != 0) ::kill(pid_, sig);
}

std::optional<ExitStatus> ChildProcess::Poll() {
    if (status_ || pid_ <= 0) return status_;
    int st = 0;
    const pid_t r = ::waitpid(pid_, &st, WNOHANG);
    if (r == pid_) status_ = FromWaitStatus(st);
    return status_;
}

std::optional<ExitStatus> ChildProcess::Wait(std::chrono::milliseconds timeout) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (!Poll()) {
        if (std::chrono::steady_clock::now() >= deadline) return std::nullopt;
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return status_;
}

ExitStatus ChildProcess::Wait() {
    if (status_ || pid_ <= 0) return status_.value_or(ExitStatus{});
    int st = 0;
    pid_t r;
    do {
        r = ::waitpid(pid_, &st, 0);
    } while (r < 0 && errno == EINTR);
    if (r != pid_) throw std::runtime_error("lost the child process '" + name_ + "'");
    status_ = FromWaitStatus(st);
    return *status_;
}

ExitStatus ChildProcess::Stop(std::chrono::milliseconds grace) {
    if (auto s = Poll()) return *s;
    Signal(SIGTERM);
    if (auto s = Wait(grace)) return *s;
    Signal(SIGKILL);
    return *Wait(std::chrono::milliseconds(5000));
}

}  // namespace gyrocal::launch
