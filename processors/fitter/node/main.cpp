// gyrocal-fitter: fits offset and sensitivity models per sensor (fitter_node.hpp for the threads,
// fitter_core.hpp for the decisions).
#include <CLI/CLI.hpp>

#include "lcmtypes/process/process_main.hpp"
#include "processors/fitter/node/fitter_node.hpp"

int main(int argc, char** argv) {
    gyrocal::fitter::node::FitterOptions o = gyrocal::fitter::node::FitterOptions::Defaults();
    CLI::App app{
        "gyrocal-fitter: fits offset and sensitivity models per sensor from PLATEAU_*, "
        "SENSITIVITY_* and NOISE_* of the current run (RUN_EVENT) and publishes COEFFS_<sensor_id> "
        "and FIT_<sensor_id> (complete or partial, excluded points, slow noise used, "
        "repeatability). --mode ramp fits every still window of a ramp run instead.",
        "gyrocal-fitter"};
    const auto validate = gyrocal::fitter::node::AddFitterOptions(app, o);
    if (auto exit_code =
            gyrocal::process::ParseCommandLine(app, argc, argv, "gyrocal-fitter", validate))
        return *exit_code;
    if (o.mode == "ramp")
        return gyrocal::process::RunUntilStopped(
            "gyrocal-fitter", [&] { gyrocal::fitter::node::RampFitterNode(o).Run(); });
    return gyrocal::process::RunUntilStopped("gyrocal-fitter",
                                             [&] { gyrocal::fitter::node::FitterNode(o).Run(); });
}
