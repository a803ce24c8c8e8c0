#pragma once
// A unit's noise estimate as the NOISE_<id> message: what gyrocal-plateau publishes and what the
// virtual lab hands the fitter core. Only the generated struct, no LCM runtime.
#include <string>

#include "gyrocal/noise_t.hpp"
#include "processors/noise/noise_tracker.hpp"

namespace gyrocal::plateau::node {

noise_t ToNoiseMessage(const std::string& sensor_id, const std::string& run_id,
                       const noise::NoiseEstimate& e);

}  // namespace gyrocal::plateau::node
