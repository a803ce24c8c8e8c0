// Latency from a gyro sample to its compensated rate over the bus, on this machine. For each case
// (N sensors x R Hz for D s) it starts the real gyrocal-compensator on its own multicast port
// (TTL 0, 4 MB receive buffer), publishes a power-on record and a coefficient set per sensor,
// waits until the compensator has applied them, then publishes GYRO_<id> samples, each stamped
// with this process's steady clock [us] as it is published; it receives every RATE_<id> (through
// the project's Bus: unbounded subscription queues) and records receive time - utime (a rate
// carries its sample's utime). Prints sent / received / lost, latency p50, p90, p99, p99.9 and
// max [us], the compensator's CPU (/proc/<pid>/stat) and the machine and its load. Every rate is
// then checked against the same library in this process, bit for bit: a latency of wrong
// numbers would mean nothing.
// Threads: a sender thread (its own Bus, publish only) and the main thread, which only
// dispatches the receiving Bus.
// Not a test: figures. Exit codes: 0 done, 1 a case failed (compensator did not start or ended,
// a rate differed, nothing received), 2 bad options.
// Run: <build>/bin/gyrocal_bench_compensator_latency [--case 4x100 --case 16x1000 ...]
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>
#include <optional>
#include <string>
#include <vector>

#include "lcmtypes/process/process_main.hpp"
#include "tests/bench/compensator/latency_run.hpp"
#include "tests/bench/support/bench_context.hpp"

namespace {

constexpr const char* kProcess = "gyrocal_bench_compensator_latency";

struct Options {
    std::vector<std::string> cases = {"4x100", "16x1000"};
    double duration_s = 20.0;
    std::string model = "extended";
    std::string lcm_url = "udpm://239.255.76.67:7930?ttl=0&recv_buf_size=4194304";
};

// "16x1000" -> 16 sensors at 1000 Hz; nullopt when not of that form or out of bounds.
std::optional<std::pair<int, double>> ParseCase(const std::string& text) {
    int sensors = 0;
    double hz = 0.0;
    int used = 0;
    if (std::sscanf(text.c_str(), "%dx%lf%n", &sensors, &hz, &used) != 2 ||
        used != static_cast<int>(text.size()))
        return std::nullopt;
    if (sensors < 1 || sensors > 64 || !(hz >= 1.0 && hz <= 10000.0)) return std::nullopt;
    return std::make_pair(sensors, hz);
}

std::string Validate(const Options& o) {
    for (const std::string& c : o.cases)
        if (!ParseCase(c))
            return "--case '" + c +
                   "' is not valid: expected SENSORSxHZ with 1-64 sensors and "
                   "1-10000 Hz, e.g. 16x1000";
    if (!gyrocal::bench::ParseModelKind(o.model))
        return "--model '" + o.model + "' is not valid: use quadratic or extended";
    if (o.lcm_url.rfind("udpm://", 0) != 0 || o.lcm_url.find("ttl=0") == std::string::npos)
        return "--lcm-url '" + o.lcm_url +
               "' is not valid: the latency is measured over this host's multicast, give a "
               "udpm:// URL with ttl=0";
    return "";
}

void PrintCase(const gyrocal::bench::LatencyCase& c, const gyrocal::bench::LatencyResult& r) {
    const auto& l = r.latency;
    std::printf("%d sensors x %.0f Hz x %.0f s, %s model (load %s -> %s)\n", c.sensors, c.rate_hz,
                c.duration_s, ToString(c.model), r.load_before.c_str(), r.load_after.c_str());
    std::printf(
        "  sent %lld  received %lld  lost %lld  stray %lld  refused by the compensator %lld\n",
        static_cast<long long>(r.sent), static_cast<long long>(r.received),
        static_cast<long long>(r.lost), static_cast<long long>(r.stray),
        static_cast<long long>(r.comp_rejected));
    std::printf("  latency [us]: p50 %.0f  p90 %.0f  p99 %.0f  p99.9 %.0f  max %.0f  mean %.0f\n",
                l.p50_us, l.p90_us, l.p99_us, l.p999_us, l.max_us, l.mean_us);
    const double per_s = r.send_wall_s > 0 ? r.comp_cpu_s / r.send_wall_s : 0.0;
    std::printf(
        "  compensator CPU %.2f s = %.1f %% of one core over %.1f s, %.1f us per sample; "
        "peak RSS %lld KiB\n",
        r.comp_cpu_s, 100.0 * per_s, r.send_wall_s,
        r.received > 0 ? 1e6 * r.comp_cpu_s / static_cast<double>(r.received) : 0.0,
        static_cast<long long>(r.comp_hwm_kb));
    std::printf("  sender behind its schedule by at most %.1f ms\n", r.behind_max_ms);
    std::printf(
        "  rates equal to this process's SensorCompensator bit for bit: %lld of %lld "
        "checked (%lld not checked: after a lost rate)\n",
        static_cast<long long>(r.checked - r.mismatched), static_cast<long long>(r.checked),
        static_cast<long long>(r.unchecked));
}

int RunAll(const Options& o) {
    std::printf("compensator %s; %s\n", GYROCAL_COMPENSATOR_EXE, o.lcm_url.c_str());
    int exit_code = 0;
    for (const std::string& text : o.cases) {
        const auto [sensors, hz] = *ParseCase(text);
        gyrocal::bench::LatencyCase c;
        c.sensors = sensors;
        c.rate_hz = hz;
        c.duration_s = o.duration_s;
        c.model = *gyrocal::bench::ParseModelKind(o.model);
        c.lcm_url = o.lcm_url;
        c.compensator_exe = GYROCAL_COMPENSATOR_EXE;
        c.log_path = "/tmp/" + std::string(kProcess) + "." + std::to_string(getpid()) + ".log";
        try {
            const gyrocal::bench::LatencyResult r = gyrocal::bench::RunLatencyCase(c);
            PrintCase(c, r);
            if (r.received == 0 || r.mismatched > 0) exit_code = 1;
        } catch (const std::exception& e) {
            std::fprintf(stderr, "%s: case %s: %s\n", kProcess, text.c_str(), e.what());
            exit_code = 1;
        }
        std::fflush(stdout);
    }
    return exit_code;
}

}  // namespace

int main(int argc, char** argv) {
    Options o;
    CLI::App app{
        "Latency from a GYRO_<id> sample to its RATE_<id> through a real gyrocal-compensator "
        "over LCM multicast on this machine (p50 ... max), with the compensator's CPU.",
        kProcess};
    app.option_defaults()->always_capture_default();  // --help shows every option's default
    app.add_option("--case", o.cases, "SENSORSxHZ, repeatable (a case per value)");
    app.add_option("--duration-s", o.duration_s, "seconds of samples per case")
        ->check(CLI::Range(0.1, 3600.0));
    app.add_option("--model", o.model,
                   "coefficient set: quadratic (the seed's) or extended "
                   "(every term kind)");
    app.add_option("--lcm-url", o.lcm_url, "udpm:// URL with ttl=0");
    app.footer("Exit codes: 0 done, 1 a case failed, 2 bad options.");
    if (auto code = gyrocal::process::ParseCommandLine(app, argc, argv, kProcess,
                                                       [&] { return Validate(o); }))
        return *code;
    gyrocal::bench::PrintContext(argc, argv);
    return RunAll(o);
}
