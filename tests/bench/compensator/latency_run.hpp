#pragma once
// One case of the compensator latency benchmark: a real gyrocal-compensator process, N sensors
// at R Hz for D seconds over LCM UDP multicast, the latency of every rate from its sample's
// publication to its reception here. See bench_compensator_latency.cpp for what is printed.
#include <cstdint>
#include <string>

#include "tests/bench/compensator/bench_inputs.hpp"
#include "tests/bench/compensator/latency_stats.hpp"

namespace gyrocal::bench {

struct LatencyCase {
    int sensors = 4;
    double rate_hz = 100.0;  // [Hz] per sensor
    double duration_s = 20.0;
    ModelKind model = ModelKind::kExtended;
    std::string lcm_url;          // udpm://...?ttl=0
    std::string compensator_exe;  // path of gyrocal-compensator
    std::string log_path;         // the compensator's stdout and stderr
};

struct LatencyResult {
    int64_t sent = 0;          // [count] gyro samples published
    int64_t received = 0;      // [count] rates received for them
    int64_t lost = 0;          // [count] sent - received
    int64_t stray = 0;         // [count] rates of an unknown sensor or seq, or repeated
    LatencySummary latency;    // receive time - sample utime, over every received rate
    double send_wall_s = 0;    // [s] first to last publication
    double behind_max_ms = 0;  // [ms] most the sender fell behind its schedule (load)
    double comp_cpu_s = 0;     // [s] compensator CPU from before the first sample to the last rate
    int64_t comp_hwm_kb = 0;   // [KiB] compensator peak resident set
    int64_t checked = 0;       // [count] rates compared with this process's SensorCompensator
    int64_t mismatched = 0;    // [count] of those not equal bit for bit
    int64_t unchecked = 0;     // [count] received after a lost rate of the same sensor (its
                               // sample may be what was lost, so the trackers may differ)
    int64_t comp_rejected = -1;  // [count] samples the compensator refused (its STATUS); -1 unknown
    std::string load_before, load_after;  // /proc/loadavg
};

// Runs one case. Throws std::runtime_error naming what did not happen (and the compensator's log)
// when the compensator does not start, does not take the coefficient sets, or ends early.
LatencyResult RunLatencyCase(const LatencyCase& c);

}  // namespace gyrocal::bench
