#pragma once
// `gyrocal analyze RUN [--sensor ID] [--json] [--db FILE] [--bin-s S] [--holdout-fraction F]
//  [--no-store] [--plot DIR | --binned] [--publish [--lcm-url URL]] [threshold options]`:
// the closed-loop model discovery (processors/analysis) on a run recorded in the database.
// Thin: reads the run's raw gyro and encoder samples, plateaus and sensitivity points through the
// store's query library, builds the analysis input with analysis::BuildSensorRun, prints the
// human report or the JSON (sensors[]), and (unless --no-store) keeps each sensor's result in the
// database's analyses table with, when an effect was added, the extended model as a coefficient
// set of source "analysis:<analysis_id>" (db::StoreAnalysis, one transaction per sensor).
// --binned: the run binned as it is read, every sensor in one pass (run_loader.hpp LoadBinnedRun):
// memory per bin, not per sample, for a day of many units; not with --plot (which draws samples).
// --plot DIR: the data files, gnuplot scripts and their PNG + SVG pictures (analysis/plot.hpp) go
// into DIR (created when its parent exists); gnuplot (Debian package gnuplot-nox) runs in DIR.
// --publish [--lcm-url URL]: after storing, each stored extended model is published on COEFFS_<id>
// (coeff_set_t, source "analysis:<analysis_id>" as stored) so a running gyrocal-compensator applies
// it; the recorder keeps it once (the store's insert is idempotent on the set's key). Needs the
// store (not with --no-store); a sensor without an added effect has nothing to publish (said).
// Exit codes: 0 analysed (whatever the verdict), 1 failure (database missing or unreadable, run
// or sensor unknown, no samples, storing failed, gnuplot missing or failing), 2 bad options (incl.
// a --plot DIR whose parent does not exist).
#include <CLI/CLI.hpp>
#include <functional>
#include <iosfwd>
#include <string>

#include "processors/analysis/analyze.hpp"

namespace gyrocal::cli {

struct AnalyzeOptions {
    std::string run_id;
    std::string sensor_id;  // "" = every sensor of the run
    std::string db = "gyrocal.db";
    bool json = false;
    // The analysis' options with their defaults (one place: processors/analysis/analyze.hpp);
    // --bin-s (analysis.bins.bin_s), the held-out stretch and the verdict's thresholds set them.
    gyrocal::analysis::AnalysisOptions analysis = gyrocal::analysis::AnalysisOptions::Defaults();
    bool store = true;         // keep the result in the database
    std::string plot_dir;      // "" = no pictures; else gnuplot PNG+SVG written here
    bool binned = false;       // bin as read (LoadBinnedRun): memory per bin; no plot_dir
    bool publish = false;      // publish each stored extended set on COEFFS_<id>
    std::string lcm_url;       // "" = $GYROCAL_LCM_URL or the default
    std::string command_line;  // recorded with the stored analysis
};

// The command body (exit code as above); messages to `err`, the report to `out`.
int RunAnalyze(const AnalyzeOptions& options, std::ostream& out, std::ostream& err);

void AddAnalyzeCommand(CLI::App& app, std::function<int()>& action);

}  // namespace gyrocal::cli
