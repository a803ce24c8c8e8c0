#pragma once
// Where a run's data came from and on which hosts it was processed, read from what the run
// recorded (runs.config_json, runs.host, recorder_host, the processes' STATUS). Pure.
//   simulated rig:  seed, noise seed, preset, units, effects switched on, profile / setpoints
//   CSV file:       the file and its SHA-256 (input_sha256, recorded by gyrocal calibrate)
//   LCM log:        the log file and its SHA-256
//   line stream:    stdin of the launcher (nothing to hash)
// A run recorded without a configuration (e.g. processes started by hand) says so.
#include <string>
#include <utility>
#include <vector>

#include "store/db/query.hpp"

namespace gyrocal::runreport {

struct DataSource {
    std::string kind;  // "simulated rig", "CSV file", "LCM log", "line stream", "not recorded"
    std::vector<std::pair<std::string, std::string>> details;  // label, value
};
DataSource SourceOf(const db::RunInfo& run);

// Each host with what ran there: "chamber-pc: run announced, gyrocal-fitter, gyrocal-recorder".
std::vector<std::pair<std::string, std::string>> Hosts(const db::RunDetail& detail);

// The first start event's setpoints and the run's reason, for the header: "stop: completed".
std::string OutcomeText(const db::RunInfo& run);

}  // namespace gyrocal::runreport
