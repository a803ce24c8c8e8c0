#pragma once
// `gyrocal compensate CSV (--coeffs FILE | --db FILE (--run RUN [--sensor ID] | --sensor ID |
//  --coeff-set-row N)) [--out FILE] [--out-of-range clip|extrapolate]
//  [--preset 610|613] [--temp-v-at-25c V] [--temp-v-per-c V]`:
// applies a coefficient set to measured data offline and writes the compensated
// rate per sample as CSV (time_s, sensor_id, rate_dps, angle_deg, temp_c, range_flag).
// Thin: the CSV is read with the producers' reader (csv::ReadCsv, stop on the first bad row), the
// sets come from the JSON export (analysis::CoeffSetsFromJson) or the store's query library, and
// analysis::CompensateRows does the work with the live compensator's library.
// Coefficient sources: --coeffs FILE (the format `gyrocal export --format json` writes); --db with
// --run RUN: the newest set of each sensor of the run (only --sensor's with --sensor); --db with
// only --sensor ID: that sensor's newest set; --db with --coeff-set-row N: that stored set.
// Exit codes: 0 written, 1 failure (bad CSV, bad or missing coefficients, a sensor without a set,
// database unreadable, output not writable), 2 bad options.
#include <CLI/CLI.hpp>
#include <cstdint>
#include <functional>
#include <iosfwd>
#include <map>
#include <optional>
#include <string>

#include "processors/model/convert.hpp"

namespace gyrocal::cli {

struct CompensateOptions {
    std::string csv_path;                      // measured data
    std::string coeffs_path;                   // JSON export; "" = from --db
    std::string db;                            // SQLite database
    std::string run_id;                        // with db
    std::string sensor_id;                     // with db: filter (with run) or newest set of sensor
    std::optional<int64_t> coeff_set_row;      // with db
    std::string out_path;                      // "" = `out`
    std::string range_policy = "extrapolate";  // the default of gyrocal-compensator --out-of-range
    std::string preset = "610";                // temperature transfer when the CSV has no temp_c
    std::optional<double> temp_v_at_25c;       // [V]
    std::optional<double> temp_v_per_c;        // [V/degC]
};

// Where coefficient sets come from (shared with `gyrocal validate`): a JSON file, or a database
// with a run (its newest set per sensor), a sensor (its newest set) or one stored set.
struct CoeffSource {
    std::string coeffs_path;  // JSON export; "" = from db
    std::string db;
    std::string run_id;                    // with db
    std::string sensor_id;                 // filter (with run or file), or newest set of sensor
    std::optional<int64_t> coeff_set_row;  // with db
};
// The sets by sensor; `origin` says where they came from. Throws analysis::OfflineError or
// db::NotFound naming the file, run, sensor or row.
std::map<std::string, model::CoeffSet> LoadCoeffSets(const CoeffSource& source,
                                                     std::string* origin);

// The command body (exit code as above); messages to `err`, the CSV to `out` unless out_path.
int RunCompensate(const CompensateOptions& options, std::ostream& out, std::ostream& err);

void AddCompensateCommand(CLI::App& app, std::function<int()>& action);

}  // namespace gyrocal::cli
