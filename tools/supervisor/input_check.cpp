#include "tools/supervisor/input_check.hpp"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>

#include "lcmtypes/launch/child_process.hpp"
#include "lcmtypes/text/number.hpp"
#include "tools/supervisor/child_errors.hpp"
#include "tools/supervisor/paths.hpp"

namespace gyrocal::supervisor {
namespace {

constexpr const char* kCsvSource = "gyrocal-csv-source";

// A scratch file for the checking child's output, removed when this goes out of scope.
struct ScratchLog {
    std::string path;
    ScratchLog() {
        const char* tmp = std::getenv("TMPDIR");
        path = std::string(tmp && *tmp ? tmp : "/tmp") + "/gyrocal-input-check-" +
               std::to_string(getpid()) + ".log";
    }
    ~ScratchLog() { std::remove(path.c_str()); }
};

std::string CsvProblem(const CalibrateOptions& o) {
    std::vector<std::string> argv = {SiblingExecutable(kCsvSource), o.input, "--check-rows",
                                     std::to_string(kCheckRows)};
    argv.insert(argv.end(), o.source_args.begin(), o.source_args.end());
    ScratchLog log;
    launch::ChildProcess check(argv, log.path, log.path);
    const std::optional<launch::ExitStatus> how = check.Wait(std::chrono::seconds(60));
    if (!how) {
        check.Stop();
        return o.input + ": the check of its first " + std::to_string(kCheckRows) +
               " rows did not end within 60 s";
    }
    if (how->exited && how->code == 0) return "";
    const std::vector<std::string> lines = ErrorLinesOf(launch::ReadLog(log.path), kCsvSource, 1);
    return lines.empty() ? std::string(kCsvSource) + " --check-rows " + how->Describe()
                         : lines.back();
}

}  // namespace

std::string LcmLogProblem(const std::string& path) {
    // lcm-logger's event records each begin with this big-endian sync word (LCM's log format).
    constexpr unsigned char kSync[4] = {0xED, 0xA1, 0xDA, 0x01};
    std::ifstream in(path, std::ios::binary);
    if (!in) return path + ": cannot be opened; give a readable LCM log file (lcm-logger)";
    unsigned char head[4] = {};
    in.read(reinterpret_cast<char*>(head), 4);
    const std::streamsize n = in.gcount();
    const std::string valid =
        "an LCM log (written by lcm-logger) starts with the sync word 0xEDA1DA01";
    if (n == 0) return path + ": the file is empty; " + valid;
    if (n < 4 || std::equal(head, head + 4, kSync) == false) {
        std::string got;
        for (std::streamsize i = 0; i < n; ++i) got += text::Printf("%02X", head[i]);
        return path + ": not an LCM log: it starts with 0x" + got + "; " + valid;
    }
    return "";
}

std::string MeasuredInputProblem(const CalibrateOptions& o) {
    switch (ParseSource(o.source)) {
        case Source::kCsv:
            return CsvProblem(o);
        case Source::kLog:
            return LcmLogProblem(o.input);
        case Source::kLines:
        case Source::kSim:
            return "";
    }
    return "";
}

}  // namespace gyrocal::supervisor
