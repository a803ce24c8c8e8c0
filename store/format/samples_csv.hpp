#pragma once
// A stored run's raw samples as the measured-data CSV (producers/csv_source/README.md): one row
// per gyro sample with the encoder angle and chamber air in force at its time and the unit's time
// since power-on (from its power records), so that the very samples go through
// `gyrocal compensate`, a spreadsheet, or another lab's tools. time_s is counted from
// csv::kDefaultStartUtime (the CSV source's default start), so replaying the file with default
// options gives back the stored utime of every sample; values are written in the shortest text
// that reads back to the same double.
#include <cstdint>
#include <ostream>
#include <string>

#include "store/db/sqlite_db.hpp"

namespace gyrocal::format {

// sensor_id "" = every sensor. Returns the rows written; throws NotFound for an unknown run and
// StoreError on a database error.
int64_t WriteRunSamplesCsv(db::Db& db, const std::string& run_id, const std::string& sensor_id,
                           std::ostream& out);

}  // namespace gyrocal::format
