// gyrocal-replay: publishes a stored run back onto LCM with its original reception timing; the
// node (and how it paces and stops) is replay_node.hpp.
#include <CLI/CLI.hpp>
#include <iostream>
#include <string>

#include "lcmtypes/process/flow_options.hpp"
#include "lcmtypes/process/process_main.hpp"
#include "lcmtypes/process/shutdown.hpp"
#include "store/replay/replay_node.hpp"

int main(int argc, char** argv) {
    using gyrocal::replay::kReplayProcess;
    auto o = gyrocal::replay::ReplayOptions::Defaults();
    CLI::App app{
        "gyrocal-replay: publishes a stored run (GYRO_*, ENCODER, CHAMBER_STATE, RUN_EVENT) back\n"
        "onto LCM with its original reception timing.\n"
        "Exit codes: 0 done (or stopped by SIGINT/SIGTERM), 1 unknown run, database or LCM\n"
        "failure, 2 bad options.",
        kReplayProcess};
    app.option_defaults()->always_capture_default();  // --help shows every option's default
    app.add_option("run", o.run_id, "run id to replay")->required();
    app.add_option("--db", o.db_path, "SQLite database file");
    app.add_option("--lcm-url", o.lcm_url, "LCM URL (default $GYROCAL_LCM_URL or udpm default)");
    app.add_option("--as-run", o.as_run,
                   "publish the run events under this run id instead (keeps a replay recorded "
                   "into the same database apart from the original)");
    gyrocal::process::AddPacingOptions(
        app, o.speed, o.max, "recorded seconds per wall second",
        "as fast as every consumer keeps up (flow control: each gyrocal "
        "process answers the replay's FLOW_MARK messages; with none "
        "answering, no timing at all)")
        ->check(CLI::Range(1e-3, 1e6));
    gyrocal::process::AddSourceFlowOptions(app, o.flow);
    app.remove_option(app.get_option("--batch-samples"));  // stored rows go out one by one
    if (auto exit_code = gyrocal::process::ParseCommandLine(app, argc, argv, kReplayProcess,
                                                            [&] { return o.flow.Validate(); }))
        return *exit_code;
    try {
        gyrocal::replay::ReplayNode node(o);
        gyrocal::process::InstallStopHandlers();
        return node.Run();
    } catch (const std::exception& e) {
        gyrocal::process::PrintError(kReplayProcess, e.what());
        return 1;
    }
}
