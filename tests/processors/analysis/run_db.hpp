#pragma once
// A simulated run with an undeclared hysteresis effect (0.5 mV branch offset, seed 601), written
// with the store's writer as the recorder would (run "R1", sensor "S01"): the database the
// `gyrocal analyze` tests work on.
#include <string>

#include "tests/processors/analysis/sim_run.hpp"

namespace gyrocal::analysis::testing {

// Returns the path of a fresh database in the temp directory (name made unique by the pid).
std::string WriteRunDb(const std::string& name);
// The same with any simulated run.
std::string WriteRunDb(const std::string& name, const SimRunOptions& options);
// Appends one simulated run (raw samples with keep_raw, encoder, power-on, plateaus, points) as
// run `run_id` with the store's writer; creates the database when missing. units > 1: units S01,
// S02, ... each the same run with k mV added to unit k's samples (k = 0, 1, ...), their gyro rows
// interleaved sample by sample as a recorder hears several units; the points and plateaus S01's.
void WriteSimRun(const std::string& path, const std::string& run_id, const SimRun& run,
                 int units = 1);
// Removes the database and its WAL side files (-wal, -shm), which read-only readers leave.
void RemoveRunDb(const std::string& path);

}  // namespace gyrocal::analysis::testing
