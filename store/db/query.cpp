#include "store/db/query.hpp"

#include <algorithm>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>

#include "store/db/central_db.hpp"
#include "store/db/central_url.hpp"
#include "store/db/schema.hpp"

namespace gyrocal::db {
namespace {

// Column list shared by GetRun/ListRuns; the counts use the (run_id, ...) indexes.
constexpr const char* kRunColumns = R"sql(
SELECT r.run_id, r.outcome, r.reason, r.software_version, r.config_json, r.command_line, r.host,
  r.recorder_version, r.recorder_host, r.started_utime, r.stopped_utime, r.first_recv_utime,
  (SELECT json_group_array(sensor_id) FROM (SELECT sensor_id FROM run_sensors s
     WHERE s.run_id = r.run_id UNION SELECT DISTINCT sensor_id FROM coeff_sets c
     WHERE c.run_id = r.run_id ORDER BY 1) AS ids),
  (SELECT coalesce(sum(n_samples), 0) FROM gyro_blocks b WHERE b.run_id = r.run_id),
  (SELECT count(*) FROM encoder_samples e WHERE e.run_id = r.run_id),
  (SELECT count(*) FROM chamber_states c WHERE c.run_id = r.run_id),
  (SELECT count(*) FROM plateaus p WHERE p.run_id = r.run_id),
  (SELECT count(*) FROM sensitivity_points s WHERE s.run_id = r.run_id),
  (SELECT count(*) FROM coeff_sets c WHERE c.run_id = r.run_id),
  (SELECT count(*) FROM raw_events x WHERE x.run_id = r.run_id),
  (SELECT coalesce(sum(seq_gaps), 0) FROM losses l WHERE l.run_id = r.run_id),
  (SELECT coalesce(sum(decode_errors), 0) FROM losses l WHERE l.run_id = r.run_id),
  (SELECT coalesce(sum(queue_drops), 0) FROM losses l WHERE l.run_id = r.run_id),
  coalesce((SELECT o.station_host || ':' || o.station_db FROM run_origins o
            WHERE o.run_id = r.run_id), '')
FROM runs r )sql";

RunInfo ReadRun(const Stmt& s) {
    RunInfo r;
    s.Read(0, r.run_id, r.outcome, r.reason, r.software_version, r.config_json, r.command_line,
           r.host, r.recorder_version, r.recorder_host, r.started_utime, r.stopped_utime,
           r.first_recv_utime);
    const std::string ids = s.Text(12);
    if (!ids.empty()) {
        for (const auto& v : nlohmann::json::parse(ids)) {
            if (v.is_string()) r.sensor_ids.push_back(v.get<std::string>());
        }
    }
    s.Read(13, r.gyro_samples, r.encoder_samples, r.chamber_states, r.plateaus,
           r.sensitivity_points, r.coeff_sets, r.raw_events, r.seq_gaps, r.decode_errors,
           r.queue_drops, r.station);
    return r;
}

// A table's columns named as the fields of its row, listed once: `sql` is the SELECT list
// ("a, b, c") and calling it on a statement makes a Row from columns 0, 1, 2 ... (row.a, row.b,
// row.c, each by Stmt::Read's type), so the list and the reading cannot drift apart.
template <class Row>
struct RowColumns {
    const char* sql;
    void (*read_fields)(const Stmt& s, Row& row);
    Row operator()(const Stmt& s) const {
        Row row;
        read_fields(s, row);
        return row;
    }
};
#define GYROCAL_READ_COLUMN(field) s.Read(col++, row.field);
#define GYROCAL_ROW_COLUMNS(Row, ...)                                                   \
    RowColumns<Row> {                                                                   \
        .sql = #__VA_ARGS__, .read_fields = [](const Stmt& s, Row& row) {               \
            int col = 0;                                                                \
            NLOHMANN_JSON_EXPAND(NLOHMANN_JSON_PASTE(GYROCAL_READ_COLUMN, __VA_ARGS__)) \
        }                                                                               \
    }

constexpr auto kPlateau =
    GYROCAL_ROW_COLUMNS(PlateauRow, run_id, sensor_id, plateau_id, utime, setpoint_c, start_utime,
                        end_utime, first_seq, last_seq, n_samples, n_excluded_motion, seq_gaps,
                        temp_mean_c, temp_std_c, temp_sem_c, temp_slope_c_per_min, gyro_mean_v,
                        gyro_std_v, gyro_sem_v, temp_mean_v, supply_mean_v, recv_utime);

constexpr auto kSensitivity = GYROCAL_ROW_COLUMNS(
    SensitivityRow, run_id, sensor_id, rotation_id, utime, start_utime, end_utime, first_seq,
    last_seq, n_samples, direction, temp_c, encoder_angle_deg, offset_v, offset_stderr_v,
    integral_v_s, sensitivity_v_per_dps, sensitivity_stderr_v_per_dps, accepted, reject_reason,
    recv_utime);

// The set's model of `role` ("offset", "sensitivity"); nullptr for another role.
ModelRow* RoleModel(CoeffSetRow& c, const std::string& role) {
    if (role == "offset") return &c.offset;
    if (role == "sensitivity") return &c.sensitivity;
    return nullptr;
}

// The sets of one chunk, by coeff_row_id, and the statement's "(?,?,...)" for them.
struct SetChunk {
    std::map<int64_t, CoeffSetRow*> by_id;
    std::string in;
    void Bind(Stmt& s) const {
        int i = 1;
        for (const auto& [id, set] : by_id) s.Bind(i++, id);
    }
};

void ReadModels(Db& db, const SetChunk& k) {
    Stmt m(db,
           "SELECT coeff_row_id, role, quantity, t0_c, temp_min_c, temp_max_c, residual_rms, "
           "n_points, condition_number, method FROM coeff_models WHERE coeff_row_id IN " +
               k.in);
    k.Bind(m);
    while (m.Step()) {
        if (ModelRow* r = RoleModel(*k.by_id.at(m.Int(0)), m.Text(1)))
            m.Read(2, r->quantity, r->t0_c, r->temp_min_c, r->temp_max_c, r->residual_rms,
                   r->n_points, r->condition_number, r->method);
    }
    Stmt t(db,
           "SELECT coeff_row_id, role, term_name, coeff FROM coeff_terms WHERE coeff_row_id IN " +
               k.in + " ORDER BY coeff_row_id, role, term_index");
    k.Bind(t);
    while (t.Step()) {
        if (ModelRow* r = RoleModel(*k.by_id.at(t.Int(0)), t.Text(1))) {
            r->term_names.push_back(t.Text(2));
            r->coeffs.push_back(t.Real(3));
        }
    }
    for (auto& [id, set] : k.by_id) {
        for (ModelRow* r : {&set->offset, &set->sensitivity}) {
            const size_t n = r->term_names.size();
            r->covariance.assign(n, std::vector<double>(n, 0.0));
        }
    }
    Stmt c(db,
           "SELECT coeff_row_id, role, row_index, col_index, value FROM coeff_covariance "
           "WHERE coeff_row_id IN " +
               k.in);
    k.Bind(c);
    while (c.Step()) {
        ModelRow* r = RoleModel(*k.by_id.at(c.Int(0)), c.Text(1));
        const auto i = static_cast<size_t>(c.Int(2));
        const auto j = static_cast<size_t>(c.Int(3));
        if (r && i < r->covariance.size() && j < r->covariance.size())
            r->covariance[i][j] = c.Real(4);
    }
}

void ReadLinks(Db& db, const SetChunk& k) {
    Stmt p(db, "SELECT coeff_row_id, plateau_id FROM coeff_set_plateaus WHERE coeff_row_id IN " +
                   k.in + " ORDER BY rowid");
    k.Bind(p);
    while (p.Step()) k.by_id.at(p.Int(0))->plateau_ids.push_back(p.Int(1));
    Stmt r(db, "SELECT coeff_row_id, rotation_id FROM coeff_set_rotations WHERE coeff_row_id IN " +
                   k.in + " ORDER BY rowid");
    k.Bind(r);
    while (r.Step()) k.by_id.at(r.Int(0))->rotation_ids.push_back(r.Int(1));
}

// The models and links of every set, read for many sets at once (a few statements per 500
// sets, not eight per set: a history over hundreds of runs at a central database is hundreds of
// round trips less), in the order one set at a time would give them.
void ReadSetDetails(Db& db, std::vector<CoeffSetInfo>& sets) {
    constexpr size_t kChunk = 500;
    for (size_t first = 0; first < sets.size(); first += kChunk) {
        SetChunk k;
        const size_t n = std::min(kChunk, sets.size() - first);
        for (size_t i = 0; i < n; ++i) k.by_id[sets[first + i].coeff_row_id] = &sets[first + i].set;
        k.in = "(";
        for (size_t i = 0; i < k.by_id.size(); ++i) k.in += i ? ",?" : "?";
        k.in += ")";
        ReadModels(db, k);
        ReadLinks(db, k);
    }
}

CoeffSetInfo ReadCoeffSet(const Stmt& s) {
    // Columns: coeff_row_id, run_id, sensor_id, coeff_set_id, source, utime, recv_utime, station
    CoeffSetInfo info;
    CoeffSetRow& c = info.set;
    s.Read(0, info.coeff_row_id, c.run_id, c.sensor_id, c.coeff_set_id, c.source, c.utime,
           c.recv_utime, info.station);
    return info;
}

constexpr const char* kCoeffColumns =
    "SELECT coeff_row_id, run_id, sensor_id, coeff_set_id, source, utime, recv_utime, "
    "coalesce((SELECT o.station_host || ':' || o.station_db FROM run_origins o "
    "WHERE o.run_id = c.run_id), '') FROM coeff_sets c ";
// Keeps the newest row of each (run, sensor, source): the set in force at the end of a run.
constexpr const char* kFinalOnly =
    " AND c.coeff_row_id = (SELECT max(coeff_row_id) FROM coeff_sets d WHERE d.run_id = c.run_id "
    "AND d.sensor_id = c.sensor_id AND d.source = c.source) ";

// The coefficient sets (with their models and links) that kCoeffColumns + `where`, its one
// parameter bound to `key`, selects, in its order.
std::vector<CoeffSetInfo> QueryCoeffSets(Db& db, const std::string& where, const std::string& key) {
    std::vector<CoeffSetInfo> sets =
        SelectAll(db, std::string(kCoeffColumns) + where, key, ReadCoeffSet);
    ReadSetDetails(db, sets);
    return sets;
}

}  // namespace

std::vector<std::string> ParseIds(const std::string& json_text) {
    std::vector<std::string> ids;
    if (json_text.empty()) return ids;
    const auto j = nlohmann::json::parse(json_text, nullptr, false);
    if (!j.is_array()) return ids;
    for (const auto& v : j) {
        if (v.is_string()) ids.push_back(v.get<std::string>());
    }
    return ids;
}

RunEventRow ReadRunEvent(const Stmt& s, int first) {
    RunEventRow e;
    s.Read(first, e.run_id, e.utime, e.event, e.reason, e.setpoint_index, e.setpoint_c);
    e.sensor_ids = ParseIds(s.Text(first + 6));
    s.Read(first + 7, e.software_version, e.config_json, e.command_line, e.host);
    return e;
}

std::unique_ptr<Db> OpenForQuery(const std::string& path) {
    if (IsCentralUrl(path)) return OpenCentralForQuery(path);
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) {
        throw StoreError("database '" + path + "' does not exist (use --db FILE)");
    }
    auto db = std::make_unique<Db>(path, Db::Mode::kReadOnly);
    int version = 0;
    try {
        version = db->UserVersion();
    } catch (const StoreError& e) {
        // A text file, or an SQLite file cut short or overwritten: say which, with SQLite's words.
        const bool damaged = (e.sqlite_code() & 0xff) == SQLITE_CORRUPT;
        throw StoreError("'" + path + "' " +
                             (damaged ? "is a damaged SQLite file (cut short or overwritten?)"
                                      : "is not an SQLite database") +
                             ": " + sqlite3_errstr(e.sqlite_code()),
                         e.sqlite_code());
    }
    if (version == kSchemaVersion) return db;
    if (version > kSchemaVersion) {
        throw StoreError("database '" + path + "' has schema version " + std::to_string(version) +
                         ", newer than this software (" + std::to_string(kSchemaVersion) + ")");
    }
    if (version == 0) throw StoreError("'" + path + "' is not a gyrocal database");
    // An older gyrocal database: migrate it (additive, one transaction per step), then read.
    db.reset();
    {
        Db rw(path, Db::Mode::kReadWrite);
        ConfigureConnection(rw);
        Migrate(rw);
    }
    return std::make_unique<Db>(path, Db::Mode::kReadOnly);
}

std::vector<RunInfo> ListRuns(Db& db, const RunFilter& f) {
    std::string sql = std::string(kRunColumns) + R"sql(
WHERE (CAST(?1 AS TEXT) IS NULL OR EXISTS (SELECT 1 FROM run_sensors s WHERE s.run_id = r.run_id AND s.sensor_id = ?1)
       OR EXISTS (SELECT 1 FROM gyro_blocks b WHERE b.run_id = r.run_id AND b.sensor_id = ?1)
       OR EXISTS (SELECT 1 FROM coeff_sets c WHERE c.run_id = r.run_id AND c.sensor_id = ?1))
  AND (CAST(?2 AS BIGINT) IS NULL OR r.first_recv_utime >= ?2)
  AND (CAST(?3 AS BIGINT) IS NULL OR r.first_recv_utime < ?3)
  AND (CAST(?4 AS TEXT) IS NULL OR r.outcome = ?4)
ORDER BY (r.run_id = '') ASC, r.first_recv_utime DESC, r.rowid DESC)sql";
    Stmt s(db, sql);
    if (f.sensor_id) s.Bind(1, *f.sensor_id);
    if (f.since_utime) s.Bind(2, *f.since_utime);
    if (f.until_utime) s.Bind(3, *f.until_utime);
    if (f.outcome) s.Bind(4, *f.outcome);
    std::vector<RunInfo> out;
    while (s.Step()) {
        RunInfo r = ReadRun(s);
        const bool empty_bucket = r.run_id.empty() && r.gyro_samples == 0 &&
                                  r.encoder_samples == 0 && r.chamber_states == 0 &&
                                  r.plateaus == 0 && r.coeff_sets == 0 && r.raw_events == 0;
        if (!empty_bucket) out.push_back(std::move(r));
    }
    return out;
}

bool RunExists(Db& db, const std::string& run_id) {
    Stmt s(db, "SELECT 1 FROM runs WHERE run_id = ?");
    s.Bind(1, run_id);
    return s.Step();
}

void RequireRun(Db& db, const std::string& run_id, const std::string& why) {
    if (!RunExists(db, run_id)) {
        throw NotFound("no run '" + run_id + "' in database '" + db.path() + "'" + why);
    }
}

bool SensorExists(Db& db, const std::string& sensor_id) {
    Stmt s(db,
           "SELECT 1 FROM sensors WHERE sensor_id = ?1 UNION ALL "
           "SELECT 1 FROM coeff_sets WHERE sensor_id = ?1 LIMIT 1");
    s.Bind(1, sensor_id);
    return s.Step();
}

RunInfo GetRun(Db& db, const std::string& run_id) {
    Stmt s(db, std::string(kRunColumns) + " WHERE r.run_id = ?");
    s.Bind(1, run_id);
    if (!s.Step()) throw NotFound("no run '" + run_id + "' in database '" + db.path() + "'");
    return ReadRun(s);
}

// The run's events in the order they were recorded.
static std::vector<RunEventRow> RunEvents(Db& db, const std::string& run_id) {
    return SelectAll(db,
                     std::string("SELECT ") + kRunEventColumns +
                         ", recv_utime FROM run_events WHERE run_id = ? ORDER BY rowid",
                     run_id, [](const Stmt& s) {
                         RunEventRow e = ReadRunEvent(s, 0);
                         e.recv_utime = s.Int(11);
                         return e;
                     });
}

// The last STATUS of each process (process, host, pid) in the run.
static std::vector<StatusRow> LastStatuses(Db& db, const std::string& run_id) {
    return SelectAll(
        db,
        "SELECT process, host, pid, state, received, published, decode_errors, seq_gaps, "
        "queue_drops, rejected, last_reject, utime, recv_utime FROM status WHERE rowid IN "
        "(SELECT max(rowid) FROM status WHERE run_id = ?1 GROUP BY process, host, pid) "
        "ORDER BY process, host, pid",
        run_id, [&run_id](const Stmt& s) {
            StatusRow st;
            st.run_id = run_id;
            s.Read(0, st.process, st.host, st.pid, st.state, st.received, st.published,
                   st.decode_errors, st.seq_gaps, st.queue_drops, st.rejected, st.last_reject,
                   st.utime, st.recv_utime);
            return st;
        });
}

RunDetail ShowRun(Db& db, const std::string& run_id) {
    RunDetail d;
    d.run = GetRun(db, run_id);
    d.plateaus = SelectAll(db,
                           std::string("SELECT ") + kPlateau.sql +
                               " FROM plateaus WHERE run_id = ? ORDER BY sensor_id, plateau_id, "
                               "plateau_row_id",
                           run_id, kPlateau);
    d.sensitivity_points =
        SelectAll(db,
                  std::string("SELECT ") + kSensitivity.sql +
                      " FROM sensitivity_points WHERE run_id = ? ORDER BY sensor_id, "
                      "rotation_id, rotation_row_id",
                  run_id, kSensitivity);
    d.coeff_sets = RunFinalCoeffs(db, run_id);
    d.fit_reports = RunFitReports(db, run_id);
    d.noise = RunNoise(db, run_id);
    d.losses = SelectAll(db,
                         "SELECT channel, seq_gaps, seq_backwards, decode_errors, queue_drops "
                         "FROM losses WHERE run_id = ? ORDER BY channel",
                         run_id, [](const Stmt& s) -> LossInfo {
                             return {s.Text(0), s.Int(1), s.Int(2), s.Int(3), s.Int(4)};
                         });
    d.events = RunEvents(db, run_id);
    d.processes = LastStatuses(db, run_id);
    d.analyses = ListAnalyses(db, run_id);
    return d;
}

std::vector<CoeffSetInfo> SensorHistory(Db& db, const std::string& sensor_id, bool final_only) {
    if (!SensorExists(db, sensor_id)) {
        throw NotFound("no sensor '" + sensor_id + "' in database '" + db.path() + "'");
    }
    return QueryCoeffSets(db,
                          std::string("WHERE c.sensor_id = ? ") + (final_only ? kFinalOnly : "") +
                              "ORDER BY c.recv_utime, c.coeff_row_id",
                          sensor_id);
}

std::vector<CoeffSetInfo> RunFinalCoeffs(Db& db, const std::string& run_id) {
    RequireRun(db, run_id);
    return QueryCoeffSets(
        db, std::string("WHERE c.run_id = ? ") + kFinalOnly + "ORDER BY c.sensor_id, c.source",
        run_id);
}

std::vector<CoeffSetInfo> RunNewestCoeffs(Db& db, const std::string& run_id) {
    RequireRun(db, run_id);
    // Newest = latest recv_utime, ties broken by insertion order (as SensorHistory orders).
    return QueryCoeffSets(db,
                          "WHERE c.run_id = ?1 AND c.coeff_row_id = (SELECT d.coeff_row_id FROM "
                          "coeff_sets d WHERE d.run_id = c.run_id AND d.sensor_id = c.sensor_id "
                          "ORDER BY d.recv_utime DESC, d.coeff_row_id DESC LIMIT 1) "
                          "ORDER BY c.sensor_id",
                          run_id);
}

std::vector<CoeffSetInfo> NewestSetOfEachSensor(Db& db) {
    // Newest = latest recv_utime, ties by insertion (SensorHistory's order); sets outside any run
    // (the run '') are not calibrations.
    return QueryCoeffSets(db,
                          "WHERE c.run_id != ?1 AND c.coeff_row_id = (SELECT d.coeff_row_id FROM "
                          "coeff_sets d WHERE d.sensor_id = c.sensor_id AND d.run_id != ?1 "
                          "ORDER BY d.recv_utime DESC, d.coeff_row_id DESC LIMIT 1) "
                          "ORDER BY c.sensor_id",
                          "");
}

std::vector<ProvenanceItem> CoeffProvenance(Db& db, int64_t coeff_row_id) {
    Stmt s(db,
           "SELECT v.kind, v.item_id, v.item_found, v.start_utime, v.end_utime, v.n_samples, "
           "(SELECT count(*) FROM gyro_blocks b JOIN gyro_samples g ON g.rowid BETWEEN "
           " b.first_rowid AND b.last_rowid AND g.run_id = b.run_id AND "
           " g.sensor_id = b.sensor_id AND g.utime BETWEEN v.start_utime AND v.end_utime "
           " WHERE b.run_id = v.run_id AND b.sensor_id = v.sensor_id AND "
           " b.max_utime >= v.start_utime AND b.min_utime <= v.end_utime "
           // Implied by the overlap (max_utime <= min_utime + the widest block's span), and
           // bounds the index range on max_utime: without it every item of a day-long run
           // scanned all of its unit's later blocks (gyrocal show: 129 s for 16 units x 24 h).
           " AND b.max_utime <= v.end_utime + "
           "   (SELECT coalesce(max(max_utime - min_utime), 0) FROM gyro_blocks)) "
           "FROM v_coeff_provenance v WHERE v.coeff_row_id = ? ORDER BY v.kind, v.item_id");
    s.Bind(1, coeff_row_id);
    std::vector<ProvenanceItem> out;
    while (s.Step()) {
        ProvenanceItem p;
        s.Read(0, p.kind, p.item_id, p.item_found, p.start_utime, p.end_utime, p.n_samples,
               p.stored_samples);
        out.push_back(p);
    }
    return out;
}

}  // namespace gyrocal::db
