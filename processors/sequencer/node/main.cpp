// gyrocal-sequencer: runs the calibration procedure (METHOD.md) over LCM: orders the chamber
// through a temperature profile, waits for every sensor's plateau, orders +90/-90 deg turntable
// moves and waits for the sensitivity points, and publishes the run's start/progress/stop.
// --profile ramp ramps continuously instead (ramp_procedure.hpp). One thread: RunLoop dispatches
// messages; all decisions are in the Runner (procedure.hpp, ramp_procedure.hpp); options in
// sequencer_options.cpp.
#include <CLI/CLI.hpp>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "lcmtypes/channels/channels.hpp"
#include "lcmtypes/process/process_main.hpp"
#include "lcmtypes/process/shutdown.hpp"
#include "processors/sequencer/node/sequencer_options.hpp"

using namespace gyrocal::sequencer::node;

int main(int argc, char** argv) {
    SequencerOptions o = SequencerOptions::Defaults();
    CLI::App app{
        "gyrocal-sequencer: runs the calibration procedure (chamber setpoints, plateaus, "
        "rotations)",
        "gyrocal-sequencer"};
    const auto validate = AddSequencerOptions(app, o);
    if (auto exit_code =
            gyrocal::process::ParseCommandLine(app, argc, argv, "gyrocal-sequencer", validate))
        return *exit_code;
    if (o.command_line.empty()) {
        std::ostringstream cl;
        for (int i = 0; i < argc; ++i) cl << (i ? " " : "") << argv[i];
        o.command_line = cl.str();
    }
    try {
        gyrocal::process::InstallStopHandlers();
        SequencerNode node(o);
        return node.Run();
    } catch (const std::exception& e) {
        gyrocal::process::PrintError("gyrocal-sequencer", e.what());
        return 1;
    }
}
