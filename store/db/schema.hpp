#pragma once
// The database schema and its migrations.
//
// Versioning: PRAGMA user_version holds the schema version; 0 is an empty (new) file. Migration
// step k brings a database from version k to k+1 inside one transaction, so a database is always
// at exactly one version. Opening runs every step from the file's version to kSchemaVersion;
// a file newer than this software is refused (never downgraded). Steps are append-only: a
// released step is never edited, a change is a new step.
//   v1: tables (runs, samples, events, coefficient sets with child tables, losses, raw events)
//   v2: recorder_sessions, provenance/summary views, query indexes
//   v3: gyro_samples loses its (run_id, sensor_id, utime) index, which cost two thirds of the
//       insert rate; gyro_blocks (per committed batch and run/sensor: rowid and utime ranges)
//       finds a run's or a sensor's samples instead
//   v4: analyses (+ v_analyses), coeff_sets_key (one row per run/sensor/coeff_set_id/source);
//       no per-row index on rates (it would halve the insert rate of the recorder's mix)
//   v7: analyses.outcome (backfilled from result_json), v_analyses shows it
//   v9: pushes (a station's record of what it pushed to a central database) and run_origins (the
//       centre's record of where each run came from); the central database runs these same steps
//       translated to PostgreSQL (central_schema.cpp)
#include <string>
#include <string_view>

#include "store/db/sqlite_db.hpp"

namespace gyrocal::db {

inline constexpr int kSchemaVersion = 9;

// Brings `db` to `target_version` (default: current). Throws StoreError naming the file when the
// file is not a gyrocal database, is newer than this software, or a step fails.
void Migrate(Db& db, int target_version = kSchemaVersion);

// The SQL of the step from `from_version` to from_version + 1, as SQLite runs it (the central
// schema translates the same text). Throws StoreError outside 0..kSchemaVersion-1.
std::string_view SchemaStep(int from_version);

// Sets WAL journal, NORMAL sync (a committed transaction survives a process crash; only an OS
// crash or power loss may lose the last commits) and foreign keys off (the recorder never
// refuses a row because its run is unknown).
void ConfigureConnection(Db& db);

}  // namespace gyrocal::db
