#pragma once
// The processes of a running graph, sampled from /proc: every descendant of one process (the
// `gyrocal calibrate` launcher and what it started), with its CPU time and resident memory over
// time, so a benchmark can say how much CPU each process spent and whether its memory stayed
// flat. Header-only beside the one benchmark that uses it.
#include <dirent.h>
#include <sys/types.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "tests/bench/support/machine.hpp"

namespace gyrocal::bench {

struct ProcTrace {
    std::string name;  // basename of argv[0]
    double cpu_s = 0;  // [s] user + system, at the last sample
    int64_t hwm_kb = 0;
    std::vector<std::pair<double, int64_t>> rss;  // (wall s since start, RSS KiB)
};

// argv[0]'s basename of a process, "" when it is gone.
inline std::string ProcName(pid_t pid) {
    std::istringstream f(ReadProcFile("/proc/" + std::to_string(pid) + "/cmdline"));
    std::string argv0;
    std::getline(f, argv0, '\0');
    const auto slash = argv0.rfind('/');
    return slash == std::string::npos ? argv0 : argv0.substr(slash + 1);
}

// Every process whose chain of parents reaches `root` (root included).
inline std::vector<pid_t> Descendants(pid_t root) {
    std::map<pid_t, pid_t> parent;
    if (DIR* d = opendir("/proc")) {
        while (dirent* e = readdir(d)) {
            const pid_t pid = static_cast<pid_t>(std::atoi(e->d_name));
            if (pid <= 0) continue;
            const std::string text = ReadProcFile("/proc/" + std::to_string(pid) + "/stat");
            const auto close = text.rfind(')');
            if (close == std::string::npos) continue;
            std::istringstream rest(text.substr(close + 2));
            std::string state;
            pid_t ppid = 0;
            rest >> state >> ppid;
            parent[pid] = ppid;
        }
        closedir(d);
    }
    std::vector<pid_t> out;
    for (const auto& [pid, ppid] : parent) {
        for (pid_t p = pid; p > 1; p = parent.count(p) ? parent[p] : 0) {
            if (p == root) {
                out.push_back(pid);
                break;
            }
        }
    }
    return out;
}

class ProcSampler {
public:
    // `rss_out`: every sample is also appended there as it is taken (t_s,pid,process,rss_kb), so
    // a run cut short keeps its trace; "" = none.
    explicit ProcSampler(pid_t root, const std::string& rss_out = "")
        : root_(root), t0_(std::chrono::steady_clock::now()) {
        if (!rss_out.empty()) {
            out_.open(rss_out);
            out_ << "t_s,pid,process,rss_kb\n";
        }
    }
    void Sample() {
        const double t =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count();
        for (pid_t pid : Descendants(root_)) {
            const ProcStats s = ReadProcStats(pid);
            if (s.cpu_s < 0) continue;
            ProcTrace& tr = traces_[pid];
            if (tr.name.empty()) tr.name = ProcName(pid);
            tr.cpu_s = s.cpu_s;
            tr.hwm_kb = std::max(tr.hwm_kb, s.hwm_kb);
            tr.rss.emplace_back(t, s.rss_kb);
            if (out_.is_open())
                out_ << t << "," << pid << "," << tr.name << "," << s.rss_kb << "\n";
        }
        if (out_.is_open()) out_.flush();
    }
    const std::map<pid_t, ProcTrace>& traces() const { return traces_; }

private:
    pid_t root_;
    std::chrono::steady_clock::time_point t0_;
    std::map<pid_t, ProcTrace> traces_;
    std::ofstream out_;
};

// RSS at fraction `from` of the trace's own span and the largest RSS after it: flat memory has
// a growth near 0 whatever the level.
struct RssGrowth {
    int64_t at_kb = 0, peak_after_kb = 0;
    int64_t growth_kb() const { return peak_after_kb - at_kb; }
};
inline RssGrowth GrowthAfter(const ProcTrace& tr, double from) {
    RssGrowth g;
    if (tr.rss.empty()) return g;
    const double t_end = tr.rss.back().first, t_begin = tr.rss.front().first;
    const double t_from = t_begin + from * (t_end - t_begin);
    bool have = false;
    for (const auto& [t, kb] : tr.rss) {
        if (t < t_from) continue;
        if (!have) {
            g.at_kb = g.peak_after_kb = kb;
            have = true;
        }
        g.peak_after_kb = std::max(g.peak_after_kb, kb);
    }
    return g;
}

}  // namespace gyrocal::bench
