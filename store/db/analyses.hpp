#pragma once
// Closed-loop analyses stored with their run (table `analyses`, view `v_analyses`), and
// coefficient sets stored directly (not heard on the bus), e.g. the extended model an analysis
// produced. SQLite only; the model-typed overloads are in model_rows.hpp (gyrocal_db).
//
// Once per key: a coefficient set is identified by (run_id, sensor_id, coeff_set_id, source).
// Storing one that is already there (the analysis stored it directly and then published it,
// and the recorder heard it) keeps the first row and returns its coeff_row_id. The check and
// the insert run in one BEGIN IMMEDIATE transaction, so the recorder and `gyrocal analyze`
// writing the same file at once cannot both insert it.
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "store/db/result_origin.hpp"
#include "store/db/rows.hpp"
#include "store/db/sqlite_db.hpp"

namespace gyrocal::db {

// One analysis of one sensor of a run (the origin: the analysed run and sensor). Figures are NaN
// (stored NULL) when not computed.
struct AnalysisRow : ResultOrigin {
    int64_t analysis_id = 0;  // set by the database (ignored on insert)
    std::string verdict;      // e.g. "no missing effect", "added temp_rate"
    // adequate, explained, partly explained, unexplained residual, ambiguous, not testable;
    // nullopt for an analysis stored before outcomes existed (NULL in the column).
    std::optional<std::string> outcome;
    std::string candidates_json = "[]";  // what was tested: [{effect, statistic, decision}]
    std::string added_json = "[]";       // what was added: [{effect, term, coefficient, ...}]
    double offset_rms_v_before = kNaN, offset_rms_v_after = kNaN;  // [V]
    double rate_rms_dps_before = kNaN, rate_rms_dps_after = kNaN;  // [deg/s]
    double drift_dph_before = kNaN, drift_dph_after = kNaN;        // [deg/h]
    double floor_rate_rms_dps = kNaN;                              // [deg/s]
    std::string result_json;              // the whole JSON result of this sensor
    std::optional<int64_t> coeff_row_id;  // the extended model stored, if any

    static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
};

struct StoredAnalysis {
    int64_t analysis_id = 0;
    std::optional<int64_t> coeff_row_id;  // nullopt when no coefficient set was given
    std::string source;                   // "analysis:<analysis_id>": publish the set with it
};

// "analysis:<id>", the source of a coefficient set an analysis produced.
std::string AnalysisSource(int64_t analysis_id);

// Opens an existing database read-write for the tools that add to it (gyrocal analyze),
// migrating it to the current schema. Throws StoreError naming the file when it is missing,
// not a gyrocal database, or newer than this software.
std::unique_ptr<Db> OpenForUpdate(const std::string& path);

// The insert alone, inside a transaction the caller holds (the recorder's batch).
int64_t InsertAnalysisRow(Db& db, const AnalysisRow& row);

// Inserts the analysis row and returns its analysis_id. Throws NotFound when the run is not in
// the database, StoreError on an empty sensor id or a write failure.
int64_t InsertAnalysis(Db& db, const AnalysisRow& row);

// Stores a coefficient set directly (recv_utime as given in the row; <= 0 = now), in one
// transaction; returns its coeff_row_id, or that of the row already stored under the same
// (run_id, sensor_id, coeff_set_id, source). Throws StoreError on an empty sensor id or source.
int64_t StoreCoeffSet(Db& db, const CoeffSetRow& set);

// The analysis and its extended model in ONE transaction: inserts the analysis, stores
// `extended` (when given) with source "analysis:<id>", run_id = row.run_id and recv_utime =
// the analysis' creation time, and links it (analyses.coeff_row_id). `extended->sensor_id`
// must equal row.sensor_id. Throws NotFound (unknown run) or StoreError; nothing is written
// then.
StoredAnalysis StoreAnalysis(Db& db, const AnalysisRow& row, const CoeffSetRow* extended = nullptr);

// The analyses of a run, oldest first (all sensors, or one). Throws NotFound on an unknown run.
std::vector<AnalysisRow> ListAnalyses(Db& db, const std::string& run_id,
                                      const std::optional<std::string>& sensor_id = {});

// Within an open transaction: inserts the set unless its key is already stored. Returns the
// coeff_row_id and whether it was inserted. Used by StoreWriter and StoreCoeffSet.
struct CoeffInsert {
    int64_t coeff_row_id = 0;
    bool inserted = false;
};
CoeffInsert InsertCoeffSetOnce(Db& db, const CoeffSetRow& set);

}  // namespace gyrocal::db
