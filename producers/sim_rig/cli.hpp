#pragma once
// Command line of gyrocal-sim-rig: every option, its default and its valid range (--help).
#include <optional>

#include "producers/sim_rig/rig_node.hpp"

namespace gyrocal::sim_rig {

// Parses and validates argv into `options`. Returns nullopt to go on, or the exit code to leave
// with: 0 after --help, 2 after a bad option (a one-line reason naming it is on stderr).
std::optional<int> ParseSimRigOptions(int argc, char** argv, SimRigOptions& options);

}  // namespace gyrocal::sim_rig
