// gyrocal-sim-rig: the simulated chamber, turntable, encoder and gyro units on LCM.
// Parses options (cli.cpp; exit 2 with a one-line reason), writes the truth sidecar if asked,
// and runs SimRigNode until SIGINT/SIGTERM, --duration-s or the end of the built-in profile.
#include <iostream>
#include <string>

#include "lcmtypes/process/process_main.hpp"
#include "lcmtypes/process/shutdown.hpp"
#include "producers/sim_rig/cli.hpp"
#include "producers/sim_rig/rig_node.hpp"
#include "producers/sim_rig/truth_file.hpp"

int main(int argc, char** argv) {
    gyrocal::sim_rig::SimRigOptions options = gyrocal::sim_rig::SimRigOptions::Defaults();
    if (const auto exit_code = gyrocal::sim_rig::ParseSimRigOptions(argc, argv, options))
        return *exit_code;
    if (!options.truth_out.empty()) {
        std::string error;
        if (!gyrocal::sim_rig::WriteTruthFile(options.truth_out, options, error)) {
            gyrocal::process::PrintError("gyrocal-sim-rig", error);
            return 2;
        }
    }
    gyrocal::process::InstallStopHandlers();
    try {
        gyrocal::sim_rig::SimRigNode node(options);
        return node.Run();
    } catch (const gyrocal::sim::ConfigError& e) {
        gyrocal::process::PrintError("gyrocal-sim-rig", e.what());
        return 2;
    } catch (const std::exception& e) {
        gyrocal::process::PrintError("gyrocal-sim-rig", e.what());
        return 1;
    }
}
