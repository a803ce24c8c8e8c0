#pragma once
// What a benchmark prints about the machine it ran on, and the CPU time of a process it started:
// figures only mean something with the machine and its load beside them. Header-only so that any
// benchmark folder can include it without a library target (the build may select components).
#include <unistd.h>

#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace gyrocal::bench {

// "AMD EPYC 7B13" ...: /proc/cpuinfo's first "model name", "unknown" when there is none.
inline std::string CpuModel() {
    std::ifstream f("/proc/cpuinfo");
    std::string line;
    while (std::getline(f, line)) {
        if (line.rfind("model name", 0) == 0) {
            const auto colon = line.find(':');
            return colon == std::string::npos ? line : line.substr(colon + 2);
        }
    }
    return "unknown";
}

inline unsigned Nproc() { return std::thread::hardware_concurrency(); }

// The 1, 5 and 15 minute load averages as /proc/loadavg writes them ("2.31 3.02 4.10").
inline std::string LoadAverage() {
    std::ifstream f("/proc/loadavg");
    std::string one, five, fifteen;
    f >> one >> five >> fifteen;
    return one.empty() ? "unknown" : one + " " + five + " " + fifteen;
}

struct ProcStats {
    double cpu_s = -1.0;  // [s] user + system CPU time; -1 when the process cannot be read
    int64_t hwm_kb = 0;   // [KiB] peak resident set
    int64_t rss_kb = 0;   // [KiB] resident set
};

// The whole text of a /proc file, "" when it cannot be read: a process may end between finding it
// and reading it (libstdc++ then throws from the read, "No such process").
inline std::string ReadProcFile(const std::string& path) {
    try {
        std::ifstream f(path);
        return std::string((std::istreambuf_iterator<char>(f)), {});
    } catch (const std::exception&) {
        return "";
    }
}

// From /proc/<pid>/stat (utime, stime: fields 14 and 15, after the parenthesised command name,
// which may itself hold spaces) and /proc/<pid>/status (VmHWM, VmRSS).
inline ProcStats ReadProcStats(pid_t pid) {
    ProcStats s;
    const std::string text = ReadProcFile("/proc/" + std::to_string(pid) + "/stat");
    const auto close = text.rfind(')');
    if (close != std::string::npos && close + 2 < text.size()) {
        std::istringstream in(text.substr(close + 2));
        std::vector<std::string> fields;
        for (std::string f; in >> f;) fields.push_back(f);
        // fields[0] is field 3 (state), so utime is fields[11] and stime fields[12].
        if (fields.size() > 12)
            s.cpu_s = (std::stod(fields[11]) + std::stod(fields[12])) /
                      static_cast<double>(sysconf(_SC_CLK_TCK));
    }
    std::istringstream status(ReadProcFile("/proc/" + std::to_string(pid) + "/status"));
    for (std::string line; std::getline(status, line);) {
        if (line.rfind("VmHWM:", 0) == 0) s.hwm_kb = std::stoll(line.substr(6));
        if (line.rfind("VmRSS:", 0) == 0) s.rss_kb = std::stoll(line.substr(6));
    }
    return s;
}

}  // namespace gyrocal::bench
