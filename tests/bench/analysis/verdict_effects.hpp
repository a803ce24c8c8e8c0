#pragma once
// Benchmark support (gyrocal_bench_verdict): offsets added to a recorded run AFTER the simulator,
// as functions of what a real unit's offset could follow - time, the measured temperature and its
// rate and acceleration, a play-operator branch, the measured supply, a slow exogenous wander that
// no channel records, random events. Both simulators get them the same way, and the same
// functions give the truth on a second (held-out) run of the unit. Shapes come from the 1 s means
// of the measured temperature, so the listed ones (rate, branch, cubic, supply, warm-up) are
// candidate-like but not the candidates' exact regressors: the listed rate is a causal 30 s
// backward difference (a boxcar kernel, not the analysis' first-order trackers); a unit's offset
// cannot follow a temperature it has not reached yet. The rate that leads the thermometer (a
// centred difference: what a unit whose thermometer lags its die by 15 s shows) is outside.
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "processors/analysis/run_data.hpp"

namespace gyrocal::bench {

// Each part [V or V per its unit]; 0 = off.
struct PostHoc {
    // Listed (a candidate of the analysis has this shape or one near it).
    double rate_v_per_c_per_s = 0;            // x dT/dt (backward over 30 s: causal)
    double branch_v = 0, branch_width_c = 3;  // x play-operator branch in [-1, 1]
    double cubic_v_per_c3 = 0;                // x (T - 25)^3
    double supply_v_per_v = 0;                // x (supply_v - 5)
    double warmup_v = 0, warmup_tau_s = 300;  // x exp(-t / tau), t from the first sample
    // Outside the list.
    double lead_rate_v_per_c_per_s = 0;        // x dT/dt centred over 30 s (leads 15 s)
    double abs_rate_v_per_c_per_s = 0;         // x |dT/dt| (centred over 120 s)
    double accel_v_per_c_per_s2 = 0;           // x d2T/dt2 (centred over 2 x 90 s)
    double quartic_v_per_c4 = 0;               // x (T - 25)^4
    double hot_bend_v = 0, hot_bend_c = 10;    // x exp((T - 70) / c)
    double drift_v_per_h = 0;                  // x t [h]
    double saw_v = 0, saw_s = 900;             // x (frac(t / P) - 0.5)
    double wander_v = 0, wander_tau_s = 2000;  // OU process (1 sigma, correlation time)
    uint64_t wander_seed = 1;
    double warmup2_v = 0, warmup2_tau_s = 600;     // a second power-on exponential
    std::vector<std::pair<double, double>> steps;  // (from t [s], offset [V])
};

struct PostHocValues {
    std::vector<double> listed_v, outside_v;  // [V] per sample of the run
};

// The parts of `p` at every sample of `run` (its samples' time from the first sample).
PostHocValues Evaluate(const PostHoc& p, const analysis::SensorRun& run);

// Adds v[i] to every sample's gyro_v.
void AddTo(analysis::SensorRun& run, const std::vector<double>& v);

}  // namespace gyrocal::bench
