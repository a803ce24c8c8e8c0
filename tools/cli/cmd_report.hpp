#pragma once
// `gyrocal report RUN|--latest [--db FILE] [--out DIR] [--limits FILE] [--json]`: writes the
// calibration report of a run (store/runreport: one self-contained HTML page) as
// DIR/report-<run>.html and prints its path and the acceptance outcome per unit.
// Exit codes: 0 report written (whatever the units' outcome), 1 failure (database missing or
// unreadable, run unknown, gnuplot missing or failing, page not writable), 2 bad options (incl. a
// limits file that does not validate, an --out DIR whose parent does not exist).
//
// Also what `gyrocal calibrate` does after a run (AfterCalibration), once the recorder has flushed:
//   --limits FILE: the run is read back from the database, analysed when a limit needs the
//     analysis (no_unexplained_residual; stored like any analysis), judged, and each unit that
//     did not pass is named with its limits; the exit code becomes 4 when the run had completed
//     (0) and a unit did not pass;
//   --report DIR: the run's report is written there (also for a failed or aborted run) and its
//     path printed; when it cannot be written a completed run's exit code becomes 1.
#include <CLI/CLI.hpp>
#include <functional>
#include <iosfwd>
#include <string>

#include "tools/supervisor/supervisor.hpp"

namespace gyrocal::cli {

// Exit code of gyrocal calibrate when the run completed but a unit did not pass its limits.
inline constexpr int kExitUnitNotAccepted = 4;

struct ReportCommandOptions {
    std::string run_id;
    bool latest = false;  // the newest run of the database instead of run_id
    std::string db = "gyrocal.db";
    std::string out_dir = ".";
    std::string limits_file;  // "" = the limits stored with the run
    bool json = false;        // print the acceptance as JSON (with the path) instead of text
};

// The command body; messages to `err`, the path and acceptance to `out`.
int RunReport(const ReportCommandOptions& options, std::ostream& out, std::ostream& err);

void AddReportCommand(CLI::App& app, std::function<int()>& action);

// The acceptance step after a calibration (supervisor.hpp: StoreServices::after_run).
int AfterCalibration(const supervisor::CalibrateOptions& options, const std::string& run_id,
                     int code);

}  // namespace gyrocal::cli
