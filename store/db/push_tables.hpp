#pragma once
// What `gyrocal push` sends of each table (push.hpp): which rows belong to a run, which columns
// hold ids that move with the run to the centre (+ run_key * 10^12), and how the rows are sent.
// Internal to push.cpp and its test; includes libpqxx.
#include <cstdint>
#include <map>
#include <pqxx/pqxx>
#include <pqxx/tablewriter>
#include <string>
#include <vector>

#include "store/db/sqlite_db.hpp"

namespace gyrocal::db::push {

// Which of a table's rows are a run's.
enum class Scope {
    kRunId,        // rows WHERE run_id = the run (most tables)
    kGyroSamples,  // the same, found through gyro_blocks' rowid ranges (no run_id index)
    kCoeffChild,   // rows of the run's coefficient sets (coeff_row_id)
    kNoiseChild,   // rows of the run's noise estimates (noise_row_id)
    kFitChild,     // rows of the run's fit reports (fit_report_row_id)
    kRunRow,       // the run's row of `runs`: inserted, or updated when the station's changed
    kLosses,       // the run's loss counters: inserted, or updated when they grew
    kSensors,      // the run's units in `sensors` (shared by every run: kept once, first wins)
    kLocal,        // not pushed: each database's own bookkeeping
};

// How a column's value changes on its way to the centre.
enum class Map {
    kNone,
    kSameRun,   // an id of a row of this run: + run_key * 10^12
    kAnyRun,    // a coefficient set's id that may be another run's: that run's key, or NULL
    kSourceId,  // coeff_sets.source 'analysis:<id>': the analysis id moves like an id
};

struct Column {
    std::string name;
    char kind = 't';  // 'i' integer, 'r' real, 't' text, 'b' blob: the declared type's affinity
    Map map = Map::kNone;
};

struct Table {
    std::string name;
    Scope scope = Scope::kLocal;
    std::string id_column;   // the station's row id: "rowid", or the INTEGER PRIMARY KEY column
    bool id_is_key = false;  // id_column is a column of the table (the centre's rowid follows it)
    std::vector<Column> columns;  // as the station file has them, in order
};

// The tables of the station file `db` as push sends them. Throws StoreError naming a table that
// push does not know (a newer schema step must classify its tables in push_tables.cpp).
std::vector<Table> StationTables(Db& db);

// The scope push gives the table `name`, and whether it knows it at all.
bool KnownTable(const std::string& name, Scope* scope);

// One run's push into an open central transaction.
struct RunCopy {
    Db& station;     // read inside one snapshot
    pqxx::work& tx;  // the central transaction
    std::string run_id;
    int64_t run_key = 0;
    int64_t rows_added = 0, rows_updated = 0, samples_added = 0;
    // Per table: the highest station id already at the centre for this run (LoadWatermarks).
    std::map<std::string, int64_t> watermarks;
};

// Reads every table's watermark for the run in one query (one round trip, not one per table).
void LoadWatermarks(const std::vector<Table>& tables, RunCopy& run);

// Sends the run's rows of `t` that the centre does not have yet.
void CopyTable(const Table& t, RunCopy& run);

}  // namespace gyrocal::db::push
