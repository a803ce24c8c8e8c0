#pragma once
// The truth sidecar file (--truth-out): written once, before the first sample, atomically.
#include <string>

#include "producers/sim_rig/rig_node.hpp"

namespace gyrocal::sim_rig {

// Writes the truth JSON of the rig `options` describes; false with `error` naming --truth-out
// and the failing step when the file cannot be written.
bool WriteTruthFile(const std::string& path, const SimRigOptions& options, std::string& error);

}  // namespace gyrocal::sim_rig
