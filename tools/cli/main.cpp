// gyrocal: the command line of the project. Each subcommand lives in its own cmd_*.cpp and sets
// `action` when chosen; main parses, then runs it.
#include <CLI/CLI.hpp>
#include <functional>
#include <iostream>
#include <sstream>

#include "gyrocal/version.hpp"
#include "store/db/query.hpp"
#include "store/recorder/recovery.hpp"
#include "tools/cli/cmd_analyze.hpp"
#include "tools/cli/cmd_calibrate.hpp"
#include "tools/cli/cmd_compensate.hpp"
#include "tools/cli/cmd_push.hpp"
#include "tools/cli/cmd_report.hpp"
#include "tools/cli/cmd_spy.hpp"
#include "tools/cli/cmd_store.hpp"
#include "tools/cli/cmd_validate.hpp"
#include "tools/cli/command.hpp"

int main(int argc, char** argv) {
    CLI::App app{"gyrocal: temperature calibration of analog MEMS gyros over LCM"};
    app.require_subcommand(1);
    app.set_version_flag("--version", std::string(gyrocal::kSoftwareVersion));
    app.footer("Exit codes: 0 success, 1 failure, 2 bad options; see each command's --help.");
    std::function<int()> action;
    // What a calibration needs of the store: the acceptance step after the run, and a restarted
    // fitter's or compensator's state read back from the database.
    gyrocal::supervisor::StoreServices store;
    store.after_run = gyrocal::cli::AfterCalibration;
    store.recovery = [](const std::string& db_path, const std::string& run_id) {
        auto db = gyrocal::db::OpenForQuery(db_path);
        gyrocal::recorder::RecoveredRun r = gyrocal::recorder::ReadRecovery(*db, run_id);
        return gyrocal::supervisor::RecoveredState{std::move(r.plateaus), std::move(r.rotations),
                                                   std::move(r.newest_coeffs)};
    };
    gyrocal::cli::AddCalibrateCommand(app, action, std::move(store));
    gyrocal::cli::AddSpyCommand(app, action);
    AddStoreCommands(app, action);
    gyrocal::cli::AddPushCommands(app, action);
    gyrocal::cli::AddAnalyzeCommand(app, action);
    gyrocal::cli::AddValidateCommand(app, action);
    gyrocal::cli::AddCompensateCommand(app, action);
    gyrocal::cli::AddReportCommand(app, action);
    return gyrocal::cli::ParseAndRun(app, argc, argv, action);
}
