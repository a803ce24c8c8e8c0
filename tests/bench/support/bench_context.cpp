#include "tests/bench/support/bench_context.hpp"

#include <sys/utsname.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <sstream>

#include "tests/bench/support/machine.hpp"

namespace gyrocal::bench {
namespace {

// `text` quoted for sh: inside single quotes, each ' written as '\''.
std::string ShellQuote(const std::string& text) {
    std::string out = "'";
    for (char c : text) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return out + "'";
}

struct CommandResult {
    int status = -1;  // the shell's exit status; -1 when it could not be started
    std::string out;  // its stdout, the trailing newline removed
};

// Runs `command` with sh, stdout captured, stderr discarded.
CommandResult Run(const std::string& command) {
    CommandResult r;
    FILE* p = popen((command + " 2>/dev/null").c_str(), "r");
    if (p == nullptr) return r;
    char buf[256];
    while (std::fgets(buf, sizeof buf, p) != nullptr) r.out += buf;
    const int status = pclose(p);
    r.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    while (!r.out.empty() && (r.out.back() == '\n' || r.out.back() == '\r')) r.out.pop_back();
    return r;
}

std::string UtcNow() {
    const std::time_t t = std::time(nullptr);
    std::tm tm{};
    gmtime_r(&t, &tm);
    char buf[32];
    std::strftime(buf, sizeof buf, "%Y-%m-%d %H:%M:%S UTC", &tm);
    return buf;
}

// "/proc/meminfo"'s "MemTotal: 8148000 kB" as 8148000; -1 when absent.
long long MeminfoKb(const std::string& key) {
    std::ifstream f("/proc/meminfo");
    for (std::string line; std::getline(f, line);)
        if (line.rfind(key + ":", 0) == 0) return std::stoll(line.substr(key.size() + 1));
    return -1;
}

std::string Memory() {
    const long long total_kb = MeminfoKb("MemTotal"), available_kb = MeminfoKb("MemAvailable");
    if (total_kb < 0) return "unknown";
    char buf[96];
    std::snprintf(buf, sizeof buf, "%.1f GiB total, %.1f GiB available", total_kb / 1048576.0,
                  available_kb / 1048576.0);
    return buf;
}

std::string Command(int argc, char** argv) {
    std::string out;
    for (int i = 0; i < argc; ++i) {
        const std::string a = argv[i];
        const bool plain = !a.empty() && a.find_first_of(" \t\"'$\\;&|<>*?()") == std::string::npos;
        out += (i > 0 ? " " : "") + (plain ? a : ShellQuote(a));
    }
    return out;
}

}  // namespace

std::string SourceCommit(const std::string& source_dir) {
    // GIT_DIR and the like in the environment would point git elsewhere than `source_dir`.
    const std::string git = "env -u GIT_DIR -u GIT_WORK_TREE -u GIT_INDEX_FILE git -C " +
                            ShellQuote(source_dir) + " --no-optional-locks ";
    if (Run("git --version").status != 0) return "unknown (git not found)";
    // --show-toplevel first: a tree copied inside another checkout is not that checkout.
    const CommandResult top = Run(git + "rev-parse --show-toplevel");
    const CommandResult head = Run(git + "rev-parse HEAD");
    char real[4096];
    const std::string resolved =
        realpath(source_dir.c_str(), real) != nullptr ? std::string(real) : source_dir;
    if (top.status != 0 || head.status != 0 || top.out != resolved)
        return "unknown (not a git checkout: " + source_dir + ")";
    const CommandResult status = Run(git + "status --porcelain --untracked-files=no");
    if (status.status != 0) return head.out + " (status unknown)";
    return head.out + (status.out.empty() ? "" : "+dirty");
}

std::vector<ContextField> ReadContext(int argc, char** argv, const std::string& source_dir) {
    std::vector<ContextField> f;
    f.emplace_back("date", UtcNow());
    f.emplace_back("command", Command(argc, argv));
    f.emplace_back("commit", SourceCommit(source_dir) + " (" + source_dir + ")");
    char host[256] = "unknown";
    gethostname(host, sizeof host - 1);
    f.emplace_back("host", host);
    f.emplace_back(
        "cpu", CpuModel() + ", " + std::to_string(sysconf(_SC_NPROCESSORS_ONLN)) + " cores online");
    f.emplace_back("memory", Memory());
    utsname u{};
    f.emplace_back("kernel", uname(&u) == 0
                                 ? std::string(u.sysname) + " " + u.release + " " + u.machine
                                 : std::string("unknown"));
    f.emplace_back("load", LoadAverage() + " (1, 5, 15 min averages, at start)");
    return f;
}

std::vector<ContextField> ReadContext(int argc, char** argv) {
    return ReadContext(argc, argv, GYROCAL_SOURCE_DIR);
}

std::string FormatContext(const std::vector<ContextField>& fields) {
    size_t width = 0;
    for (const auto& [key, value] : fields) width = std::max(width, key.size());
    std::ostringstream out;
    for (const auto& [key, value] : fields)
        out << key << ':' << std::string(width - key.size() + 1, ' ') << value << '\n';
    return out.str();
}

void PrintContext(int argc, char** argv) {
    std::fputs(FormatContext(ReadContext(argc, argv)).c_str(), stdout);
    std::fflush(stdout);
}

}  // namespace gyrocal::bench
