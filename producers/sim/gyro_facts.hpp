#pragma once
// What the simulated rig's gyro type tells a fitter that calibrates it, as a lab would know it of
// a real gyro type: the slow noise an Allan-deviation characterisation of the type gives in a
// plateau mean (bias instability and rate random walk at the rig's default noise settings; not a
// unit's truth) and the module preset's nominal sensitivity. The rig knows its gyros, so the
// choice lives here; `gyrocal calibrate --source sim` passes these to gyrocal-fitter.
#include <string>

namespace gyrocal::sim {

struct SimulatedGyroFacts {
    double plateau_slow_noise_dps = 0.0;         // [deg/s] in a plateau mean of average_s
    double nominal_sensitivity_v_per_dps = 0.0;  // [V/(deg/s)] of the preset
};

// `preset`: "610" or "613" (throws ConfigError otherwise). `average_s` [s]: the plateau's
// averaging window; the rate random walk's share is taken over about an hour of run (~1 %).
SimulatedGyroFacts FactsOfSimulatedGyros(const std::string& preset, double average_s = 60.0);

}  // namespace gyrocal::sim
