#pragma once
// `gyrocal analyze RUN [--sensor ID] [--json] [--db FILE] [--bin-s S] [--holdout-fraction F]`:
// the closed-loop model discovery (processors/analysis) on a run recorded in the database.
// Thin: reads the run's raw gyro and encoder samples, plateaus and sensitivity points through the
// store's query library, builds the analysis input with analysis::BuildSensorRun, prints the
// human report or the JSON (sensors[]), and (unless --no-store) keeps each sensor's result in the
// database's analyses table with, when an effect was added, the extended model as a coefficient
// set of source "analysis:<analysis_id>" (store::StoreAnalysis, one transaction per sensor).
// Exit codes: 0 analysed (whatever the verdict), 1 failure (database missing or unreadable, run
// or sensor unknown, no samples, storing failed), 2 bad options.
#include <CLI/CLI.hpp>
#include <functional>
#include <iosfwd>
#include <string>

namespace gyrocal::cli {

struct AnalyzeOptions {
    std::string run_id;
    std::string sensor_id;  // "" = every sensor of the run
    std::string db = "gyrocal.db";
    bool json = false;
    double bin_s = 10.0;  // [s]
    double holdout_fraction = 0.25;
    bool store = true;         // keep the result in the database
    std::string command_line;  // recorded with the stored analysis
};

// The command body (exit code as above); messages to `err`, the report to `out`.
int RunAnalyze(const AnalyzeOptions& options, std::ostream& out, std::ostream& err);

void AddAnalyzeCommand(CLI::App& app, std::function<int()>& action);

}  // namespace gyrocal::cli
