#include "producers/sim/gyro_facts.hpp"

#include <cmath>

#include "producers/sim/config.hpp"
#include "producers/sim/noise.hpp"

namespace gyrocal::sim {

SimulatedGyroFacts FactsOfSimulatedGyros(const std::string& preset, double average_s) {
    SimulatedGyroFacts f;
    f.plateau_slow_noise_dps = std::sqrt(SlowNoiseBinVariance(NoiseConfig{}, average_s, 3600.0));
    f.nominal_sensitivity_v_per_dps = PresetByName(preset).sensitivity_v_per_dps;
    return f;
}

}  // namespace gyrocal::sim
