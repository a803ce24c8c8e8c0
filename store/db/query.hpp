#pragma once
// The questions people ask of the database, as functions returning plain structs. All SQL uses
// bound parameters only: ids and filters from a command line never become SQL text.
// Readers open the file read-only; a missing file or a non-gyrocal file throws StoreError.
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "store/db/analyses.hpp"
#include "store/db/fit_query.hpp"
#include "store/db/rows.hpp"
#include "store/db/sqlite_db.hpp"

namespace gyrocal::db {

// Thrown when a run or sensor named by the user is not in the database.
class NotFound : public StoreError {
public:
    using StoreError::StoreError;
};

// Opens an existing database for reading and checks its schema version (an older version is
// read through the current views only after the recorder migrated it: refused with a message).
std::unique_ptr<Db> OpenForQuery(const std::string& path);

struct RunFilter {
    std::optional<std::string> sensor_id;  // runs that recorded this sensor
    std::optional<int64_t> since_utime;    // [us] wall clock: runs first seen at or after
    std::optional<int64_t> until_utime;    // [us] wall clock: runs first seen before
    std::optional<std::string> outcome;    // 'running', 'stop', 'abort', 'none'
};

struct RunInfo {
    std::string run_id, outcome, reason, software_version, config_json, command_line, host,
        recorder_version, recorder_host;
    std::optional<int64_t> started_utime, stopped_utime, first_recv_utime;
    std::vector<std::string> sensor_ids;
    int64_t gyro_samples = 0, encoder_samples = 0, chamber_states = 0, plateaus = 0,
            sensitivity_points = 0, coeff_sets = 0, raw_events = 0;
    int64_t seq_gaps = 0, decode_errors = 0, queue_drops = 0;
    // At a central database: the station the run was pushed from ("host:file", run_origins);
    // "" in a station's own file.
    std::string station;
};

struct LossInfo {
    std::string channel;
    int64_t seq_gaps = 0, seq_backwards = 0, decode_errors = 0, queue_drops = 0;
};

struct CoeffSetInfo {
    int64_t coeff_row_id = 0;
    CoeffSetRow set;      // models, links, ids
    std::string station;  // at a central database: the run's station ("host:file"); else ""
};

struct RunDetail {
    RunInfo run;
    std::vector<PlateauRow> plateaus;
    std::vector<SensitivityRow> sensitivity_points;
    std::vector<CoeffSetInfo> coeff_sets;
    std::vector<LossInfo> losses;
    std::vector<RunEventRow> events;
    std::vector<StatusRow> processes;   // last STATUS of each process (name, host, pid) in the run
    std::vector<AnalysisRow> analyses;  // closed-loop analyses of the run, oldest first
    std::vector<FitReportInfo> fit_reports;  // final report of each sensor and source (v5)
    std::vector<NoiseInfo> noise;            // newest noise estimate of each sensor (v5)
};

// Newest first (by first reception); the no-run bucket '' last, listed only when not empty.
std::vector<RunInfo> ListRuns(Db& db, const RunFilter& filter);
// Throws NotFound naming the run.
RunInfo GetRun(Db& db, const std::string& run_id);
RunDetail ShowRun(Db& db, const std::string& run_id);

bool RunExists(Db& db, const std::string& run_id);
// Throws NotFound "no run 'ID' in database 'PATH'" followed by `why` unless the run exists.
void RequireRun(Db& db, const std::string& run_id, const std::string& why = "");
bool SensorExists(Db& db, const std::string& sensor_id);

// Every coefficient set of a sensor, oldest first. `final_only`: only the newest set of each
// (run, source), i.e. one per calibration. Throws NotFound when the sensor is unknown.
std::vector<CoeffSetInfo> SensorHistory(Db& db, const std::string& sensor_id, bool final_only);
// Final coefficient set of each sensor AND source of a run (e.g. the fitter's and an
// analysis'), by sensor then source. Throws NotFound.
std::vector<CoeffSetInfo> RunFinalCoeffs(Db& db, const std::string& run_id);
// The newest coefficient set of each sensor of a run, whatever its source (what an export of
// the run gives: an analysis' extended model stored after the fitter's set wins). Throws NotFound.
std::vector<CoeffSetInfo> RunNewestCoeffs(Db& db, const std::string& run_id);

// The newest coefficient set of every sensor recorded in a run, whatever its source (as an export
// of the sensor gives), by sensor: the fleet view's units.
std::vector<CoeffSetInfo> NewestSetOfEachSensor(Db& db);

// Provenance of a coefficient set: each plateau/rotation and how many raw samples it covers.
struct ProvenanceItem {
    std::string kind;  // "plateau" or "rotation"
    int64_t item_id = 0;
    bool item_found = false;
    std::optional<int64_t> start_utime, end_utime, n_samples;
    int64_t stored_samples = 0;  // gyro_samples rows of the run and sensor in [start, end]
};
std::vector<ProvenanceItem> CoeffProvenance(Db& db, int64_t coeff_row_id);

// A JSON array of strings (run_events.sensor_ids_json) as a vector; [] when malformed.
std::vector<std::string> ParseIds(const std::string& json_text);

// The columns of run_events that make a RunEventRow, in ReadRunEvent's order (recv_utime apart:
// the replay reads it first, the run detail last).
inline constexpr const char* kRunEventColumns =
    "run_id, utime, event, reason, setpoint_index, setpoint_c, sensor_ids_json, "
    "software_version, config_json, command_line, host";
// Reads kRunEventColumns from column `first` on (recv_utime is left 0).
RunEventRow ReadRunEvent(const Stmt& s, int first);

}  // namespace gyrocal::db
