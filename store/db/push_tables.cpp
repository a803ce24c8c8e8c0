#include "store/db/push_tables.hpp"

#include <charconv>
#include <cmath>
#include <map>
#include <optional>

#include "store/db/central_db.hpp"

namespace gyrocal::db::push {
namespace {

struct Known {
    Scope scope;
    std::vector<std::pair<const char*, Map>> maps;  // columns whose ids move with the run
};

// Every table of the station schema (schema.cpp), classified. A table missing here stops the
// push with its name: a new schema step must say how its rows reach the centre.
const std::map<std::string, Known>& Classification() {
    static const std::map<std::string, Known> k = {
        {"gyrocal_meta", {Scope::kLocal, {}}},
        {"recorder_sessions", {Scope::kLocal, {}}},  // the station's recorder processes
        {"pushes", {Scope::kLocal, {}}},
        {"run_origins", {Scope::kLocal, {}}},
        {"runs", {Scope::kRunRow, {}}},
        {"losses", {Scope::kLosses, {}}},
        {"sensors", {Scope::kSensors, {}}},
        {"run_sensors", {Scope::kRunId, {}}},
        {"gyro_samples", {Scope::kGyroSamples, {}}},
        {"gyro_blocks",
         {Scope::kRunId, {{"first_rowid", Map::kSameRun}, {"last_rowid", Map::kSameRun}}}},
        {"encoder_samples", {Scope::kRunId, {}}},
        {"chamber_states", {Scope::kRunId, {}}},
        {"chamber_cmds", {Scope::kRunId, {}}},
        {"turntable_cmds", {Scope::kRunId, {}}},
        {"plateau_states", {Scope::kRunId, {}}},
        {"plateaus", {Scope::kRunId, {}}},
        {"sensitivity_points", {Scope::kRunId, {}}},
        {"coeff_sets", {Scope::kRunId, {{"source", Map::kSourceId}}}},
        {"coeff_models", {Scope::kCoeffChild, {{"coeff_row_id", Map::kSameRun}}}},
        {"coeff_terms", {Scope::kCoeffChild, {{"coeff_row_id", Map::kSameRun}}}},
        {"coeff_covariance", {Scope::kCoeffChild, {{"coeff_row_id", Map::kSameRun}}}},
        {"coeff_set_plateaus", {Scope::kCoeffChild, {{"coeff_row_id", Map::kSameRun}}}},
        {"coeff_set_rotations", {Scope::kCoeffChild, {{"coeff_row_id", Map::kSameRun}}}},
        {"rates", {Scope::kRunId, {}}},
        {"status", {Scope::kRunId, {}}},
        {"run_events", {Scope::kRunId, {}}},
        {"raw_events", {Scope::kRunId, {}}},
        {"analyses", {Scope::kRunId, {{"coeff_row_id", Map::kSameRun}}}},
        {"power_states", {Scope::kRunId, {}}},
        {"validations", {Scope::kRunId, {{"coeff_row_id", Map::kAnyRun}}}},
        {"noise_estimates", {Scope::kRunId, {}}},
        {"noise_adev", {Scope::kNoiseChild, {{"noise_row_id", Map::kSameRun}}}},
        {"fit_reports", {Scope::kRunId, {}}},
        {"fit_exclusions", {Scope::kFitChild, {{"fit_report_row_id", Map::kSameRun}}}},
        {"repeatability", {Scope::kRunId, {{"fit_report_row_id", Map::kSameRun}}}},
    };
    return k;
}

// SQLite's affinity of a declared type (https://sqlite.org/datatype3.html, 3.1).
char Affinity(std::string type) {
    for (char& c : type) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    if (type.find("INT") != std::string::npos) return 'i';
    if (type.find("CHAR") != std::string::npos || type.find("CLOB") != std::string::npos ||
        type.find("TEXT") != std::string::npos)
        return 't';
    if (type.empty() || type.find("BLOB") != std::string::npos) return 'b';
    return 'r';
}

std::string ColumnList(const Table& t) {
    std::string s;
    for (const Column& c : t.columns) s += (s.empty() ? "" : ", ") + c.name;
    return s;
}

// The station's rows of the run above the watermark ?2, id first, in id order.
std::string StationSelect(const Table& t) {
    const std::string head = "SELECT " + t.id_column + ", " + ColumnList(t) + " FROM " + t.name;
    const std::string above = " AND " + t.id_column + " > ?2 ORDER BY " + t.id_column;
    switch (t.scope) {
        case Scope::kGyroSamples:
            return head +
                   " WHERE rowid BETWEEN max(?2 + 1, (SELECT min(first_rowid) FROM gyro_blocks "
                   "WHERE run_id = ?1)) AND (SELECT max(last_rowid) FROM gyro_blocks WHERE "
                   "run_id = ?1) AND run_id = ?1 ORDER BY rowid";
        case Scope::kCoeffChild:
            return head +
                   " WHERE coeff_row_id IN (SELECT coeff_row_id FROM coeff_sets WHERE "
                   "run_id = ?1)" +
                   above;
        case Scope::kNoiseChild:
            return head +
                   " WHERE noise_row_id IN (SELECT noise_row_id FROM noise_estimates "
                   "WHERE run_id = ?1)" +
                   above;
        case Scope::kFitChild:
            return head +
                   " WHERE fit_report_row_id IN (SELECT fit_report_row_id FROM "
                   "fit_reports WHERE run_id = ?1)" +
                   above;
        case Scope::kSensors:
            return head +
                   " WHERE sensor_id IN (SELECT sensor_id FROM run_sensors WHERE run_id = "
                   "?1 UNION SELECT sensor_id FROM coeff_sets WHERE run_id = ?1)" +
                   above;
        default:
            return head + " WHERE run_id = ?1" + above;
    }
}

std::string Real(double v) {
    if (std::isinf(v)) return v > 0 ? "Infinity" : "-Infinity";
    char buf[32];
    const auto r = std::to_chars(buf, buf + sizeof buf, v);  // shortest exact text
    return std::string(buf, r.ptr);
}

std::string Hex(const std::vector<uint8_t>& bytes) {
    static const char* kHex = "0123456789abcdef";
    std::string s = "\\x";
    for (uint8_t b : bytes) {
        s += kHex[b >> 4];
        s += kHex[b & 15];
    }
    return s;
}

// The centre's value of column `c` (col in the statement) of the current row, as text.
struct Mapper {
    const RunCopy& run;
    std::map<int64_t, std::optional<int64_t>> any_run;  // station coeff_row_id -> central id

    int64_t Offset() const { return run.run_key * kRunKeyScale; }

    std::optional<std::string> Value(const Stmt& s, int col, const Column& c) const {
        if (s.IsNull(col)) return std::nullopt;
        switch (c.map) {
            case Map::kSameRun:
                return std::to_string(s.Int(col) + Offset());
            case Map::kAnyRun: {
                const auto it = any_run.find(s.Int(col));
                if (it == any_run.end() || !it->second) return std::nullopt;
                return std::to_string(*it->second);
            }
            case Map::kSourceId: {
                std::string v = s.Text(col);
                const std::string prefix = "analysis:";
                if (v.rfind(prefix, 0) == 0 && v.size() > prefix.size() &&
                    v.find_first_not_of("0123456789", prefix.size()) == std::string::npos)
                    v = prefix + std::to_string(std::stoll(v.substr(prefix.size())) + Offset());
                return v;
            }
            case Map::kNone:
                break;
        }
        switch (c.kind) {
            case 'i':
                return std::to_string(s.Int(col));
            case 'r':
                return Real(s.Real(col));
            case 'b':
                return Hex(s.Blob(col));
            default:
                return s.Text(col);
        }
    }
};

void AppendCopyField(std::string& line, const std::optional<std::string>& v) {
    if (!line.empty()) line += '\t';
    if (!v) {
        line += "\\N";
        return;
    }
    for (char ch : *v) {
        switch (ch) {
            case '\\':
                line += "\\\\";
                break;
            case '\t':
                line += "\\t";
                break;
            case '\n':
                line += "\\n";
                break;
            case '\r':
                line += "\\r";
                break;
            default:
                line += ch;
        }
    }
}

// The central columns a row is written to: the station's, after the centre's rowid unless the
// table's id is one of its columns (then the centre's rowid is generated from it).
std::vector<std::string> CentralColumns(const Table& t) {
    std::vector<std::string> cols;
    if (!t.id_is_key) cols.push_back("rowid");
    for (const Column& c : t.columns) cols.push_back(c.name);
    return cols;
}

// The highest station id of `t` already at the centre for this run (0: none).
int64_t Watermark(const Table& t, RunCopy& run) {
    const auto it = run.watermarks.find(t.name);
    if (it != run.watermarks.end()) return it->second;
    const int64_t lo = run.run_key * kRunKeyScale;
    const pqxx::result r =
        run.tx.exec_params("SELECT max(" + t.id_column + ") FROM " + t.name + " WHERE " +
                               t.id_column + " >= $1 AND " + t.id_column + " < $2",
                           lo, lo + kRunKeyScale);
    return r[0][0].is_null() ? 0 : r[0][0].as<int64_t>() - lo;
}

// Where the validations of the run point to coefficient sets (maybe of other runs): the
// central id of each, or nullopt when that run is not at the centre.
void ResolveAnyRun(const Table& t, RunCopy& run, Mapper& m) {
    bool needed = false;
    for (const Column& c : t.columns) needed = needed || c.map == Map::kAnyRun;
    if (!needed) return;
    Stmt s(run.station,
           "SELECT c.coeff_row_id, c.run_id FROM coeff_sets c WHERE c.coeff_row_id IN (SELECT "
           "coeff_row_id FROM " +
               t.name + " WHERE run_id = ?1)");
    s.Bind(1, run.run_id);
    while (s.Step()) {
        const int64_t id = s.Int(0);
        const std::string owner = s.Text(1);
        if (owner == run.run_id) {
            m.any_run[id] = id + m.Offset();
            continue;
        }
        // That run at the centre, if it is the same run (start, first reception, host).
        Stmt who(run.station,
                 "SELECT coalesce(started_utime, ''), coalesce(first_recv_utime, ''), host FROM "
                 "runs WHERE run_id = ?1");
        who.Bind(1, owner);
        if (!who.Step()) {
            m.any_run[id] = std::nullopt;
            continue;
        }
        const pqxx::result k = run.tx.exec_params(
            "SELECT o.run_key FROM run_origins o JOIN runs r ON r.run_id = o.run_id WHERE "
            "o.run_id = $1 AND coalesce(r.started_utime::text, '') = $2 AND "
            "coalesce(r.first_recv_utime::text, '') = $3 AND r.host = $4",
            owner, who.Text(0), who.Text(1), who.Text(2));
        m.any_run[id] = k.empty()
                            ? std::nullopt
                            : std::optional<int64_t>(id + k[0][0].as<int64_t>() * kRunKeyScale);
    }
}

// A run's rows of a table the centre only appends to, sent with COPY.
void CopyRows(const Table& t, RunCopy& run) {
    Mapper m{run, {}};
    ResolveAnyRun(t, run, m);
    const int64_t mark = Watermark(t, run);
    Stmt s(run.station, StationSelect(t));
    s.Bind(1, run.run_id).Bind(2, mark);
    if (!s.Step()) return;
    const std::vector<std::string> cols = CentralColumns(t);
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wdeprecated-declarations"
    // libpqxx 6's tablewriter takes lines as they are: COPY text format, escaped here.
    pqxx::tablewriter w(run.tx, t.name, cols.begin(), cols.end());
#pragma GCC diagnostic pop
    std::string line;
    int64_t n = 0;
    do {
        line.clear();
        if (!t.id_is_key) AppendCopyField(line, std::to_string(s.Int(0) + m.Offset()));
        for (size_t i = 0; i < t.columns.size(); ++i)
            AppendCopyField(line, m.Value(s, static_cast<int>(i) + 1, t.columns[i]));
        w.write_raw_line(line);
        ++n;
    } while (s.Step());
    w.complete();
    run.rows_added += n;
    if (t.scope == Scope::kGyroSamples) run.samples_added += n;
}

// INSERT ... VALUES of one row (its values as text, NULL as nullptr), optionally ON CONFLICT.
pqxx::result InsertRow(RunCopy& run, const Table& t,
                       const std::vector<std::optional<std::string>>& v, const std::string& tail) {
    const std::vector<std::string> cols = CentralColumns(t);
    std::string sql = "INSERT INTO " + t.name + " (";
    std::string params;
    for (size_t i = 0; i < cols.size(); ++i) {
        sql += (i ? ", " : "") + cols[i];
        params += (i ? ", $" : "$") + std::to_string(i + 1);
    }
    std::vector<const char*> ptrs;
    for (const auto& x : v) ptrs.push_back(x ? x->c_str() : nullptr);
    return run.tx.exec_params(sql + ") VALUES (" + params + ") " + tail,
                              pqxx::prepare::make_dynamic_params(ptrs));
}

// The station row of the statement's current row, as the centre's values (rowid first unless
// the id is a column).
std::vector<std::optional<std::string>> RowValues(const Table& t, const Stmt& s, const Mapper& m) {
    std::vector<std::optional<std::string>> v;
    if (!t.id_is_key) v.push_back(std::to_string(s.Int(0) + m.Offset()));
    for (size_t i = 0; i < t.columns.size(); ++i)
        v.push_back(m.Value(s, static_cast<int>(i) + 1, t.columns[i]));
    return v;
}

// Rows keyed by `key` (runs: run_id; losses: channel) that a station may change while its run is
// open: inserted when absent, updated when different.
void UpsertRows(const Table& t, RunCopy& run, const std::string& key) {
    Mapper m{run, {}};
    Stmt s(run.station, "SELECT " + t.id_column + ", " + ColumnList(t) + " FROM " + t.name +
                            " WHERE run_id = ?1 ORDER BY " + t.id_column);
    s.Bind(1, run.run_id);
    size_t key_col = 0;
    while (key_col < t.columns.size() && t.columns[key_col].name != key) ++key_col;
    while (s.Step()) {
        const auto v = RowValues(t, s, m);
        const auto& key_value = v[key_col + (t.id_is_key ? 0 : 1)];
        const pqxx::result have =
            run.tx.exec_params("SELECT " + ColumnList(t) + " FROM " + t.name +
                                   " WHERE run_id = $1 AND " + key + " = $2",
                               run.run_id, key_value ? *key_value : std::string());
        if (have.empty()) {
            InsertRow(run, t, v, "");
            ++run.rows_added;
            continue;
        }
        std::string set;
        std::vector<const char*> ptrs;
        for (size_t i = 0; i < t.columns.size(); ++i) {
            const auto& mine = v[i + (t.id_is_key ? 0 : 1)];
            const pqxx::field f = have[0][static_cast<int>(i)];
            const bool same = f.is_null() ? !mine : (mine && *mine == f.c_str());
            if (same) continue;
            ptrs.push_back(mine ? mine->c_str() : nullptr);
            set += (set.empty() ? "" : ", ") + t.columns[i].name + " = $" +
                   std::to_string(ptrs.size() + 2);
        }
        if (set.empty()) continue;
        std::vector<const char*> all = {run.run_id.c_str(), key_value ? key_value->c_str() : ""};
        all.insert(all.end(), ptrs.begin(), ptrs.end());
        run.tx.exec_params(
            "UPDATE " + t.name + " SET " + set + " WHERE run_id = $1 AND " + key + " = $2",
            pqxx::prepare::make_dynamic_params(all));
        ++run.rows_updated;
    }
}

// The run's units: each sensor is one row for the whole lab, the first station's.
void InsertSensors(const Table& t, RunCopy& run) {
    Mapper m{run, {}};
    Stmt s(run.station, StationSelect(t));
    s.Bind(1, run.run_id).Bind(2, int64_t{0});
    while (s.Step())
        run.rows_added +=
            InsertRow(run, t, RowValues(t, s, m), "ON CONFLICT DO NOTHING").affected_rows();
}

}  // namespace

bool KnownTable(const std::string& name, Scope* scope) {
    const auto& k = Classification();
    const auto it = k.find(name);
    if (it == k.end()) return false;
    if (scope) *scope = it->second.scope;
    return true;
}

std::vector<Table> StationTables(Db& db) {
    std::vector<Table> out;
    Stmt names(db,
               "SELECT name FROM sqlite_master WHERE type = 'table' AND name NOT LIKE 'sqlite_%' "
               "ORDER BY rowid");
    while (names.Step()) {
        Table t;
        t.name = names.Text(0);
        const auto it = Classification().find(t.name);
        if (it == Classification().end()) {
            throw StoreError("database '" + db.path() + "': table '" + t.name +
                             "' is not known to gyrocal push (a newer schema? classify it in "
                             "store/db/push_tables.cpp)");
        }
        t.scope = it->second.scope;
        Stmt info(db, "SELECT name, type, pk FROM pragma_table_info(?1) ORDER BY cid");
        info.Bind(1, t.name);
        int keys = 0;
        std::string key;
        while (info.Step()) {
            Column c{info.Text(0), Affinity(info.Text(1)), Map::kNone};
            for (const auto& [col, map] : it->second.maps)
                if (c.name == col) c.map = map;
            if (info.Int(2) > 0) {
                ++keys;
                if (c.kind == 'i' && info.Text(1) == "INTEGER") key = c.name;
            }
            t.columns.push_back(c);
        }
        t.id_is_key = keys == 1 && !key.empty();
        t.id_column = t.id_is_key ? key : "rowid";
        for (Column& c : t.columns)  // the row's own id moves with the run like the others
            if (t.id_is_key && c.name == key) c.map = Map::kSameRun;
        out.push_back(std::move(t));
    }
    return out;
}

void LoadWatermarks(const std::vector<Table>& tables, RunCopy& run) {
    std::string sql;
    std::vector<const Table*> copied;
    for (const Table& t : tables) {
        if (t.scope == Scope::kLocal || t.scope == Scope::kRunRow || t.scope == Scope::kLosses ||
            t.scope == Scope::kSensors)
            continue;
        sql += std::string(sql.empty() ? "SELECT " : ", ") + "(SELECT max(" + t.id_column +
               ") - $1 FROM " + t.name + " WHERE " + t.id_column + " >= $1 AND " + t.id_column +
               " < $2)";
        copied.push_back(&t);
    }
    if (copied.empty()) return;
    const int64_t lo = run.run_key * kRunKeyScale;
    const pqxx::result r = run.tx.exec_params(sql, lo, lo + kRunKeyScale);
    for (size_t i = 0; i < copied.size(); ++i) {
        const pqxx::field f = r[0][static_cast<int>(i)];
        run.watermarks[copied[i]->name] = f.is_null() ? 0 : f.as<int64_t>();
    }
}

void CopyTable(const Table& t, RunCopy& run) {
    switch (t.scope) {
        case Scope::kLocal:
            return;
        case Scope::kRunRow:
            return UpsertRows(t, run, "run_id");
        case Scope::kLosses:
            return UpsertRows(t, run, "channel");
        case Scope::kSensors:
            return InsertSensors(t, run);
        default:
            return CopyRows(t, run);
    }
}

}  // namespace gyrocal::db::push
