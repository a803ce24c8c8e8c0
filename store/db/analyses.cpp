#include "store/db/analyses.hpp"

#include <filesystem>

#include "store/db/central_url.hpp"
#include "store/db/query.hpp"
#include "store/db/schema.hpp"
#include "store/db/utc_text.hpp"

namespace gyrocal::db {
namespace {

void InsertModel(Db& db, int64_t coeff_row_id, const char* role, const ModelRow& m) {
    Stmt s(db,
           "INSERT INTO coeff_models(coeff_row_id, role, quantity, num_terms, t0_c, temp_min_c, "
           "temp_max_c, residual_rms, n_points, condition_number, method) "
           "VALUES (?,?,?,?,?,?,?,?,?,?,?)");
    s.Bind(1, coeff_row_id).Bind(2, role).Bind(3, m.quantity);
    s.Bind(4, static_cast<int64_t>(m.term_names.size())).Bind(5, m.t0_c).Bind(6, m.temp_min_c);
    s.Bind(7, m.temp_max_c).Bind(8, m.residual_rms).Bind(9, m.n_points);
    s.Bind(10, m.condition_number).Bind(11, m.method).Run();
    Stmt t(db,
           "INSERT INTO coeff_terms(coeff_row_id, role, term_index, term_name, coeff) "
           "VALUES (?,?,?,?,?)");
    for (size_t i = 0; i < m.term_names.size(); ++i) {
        t.Bind(1, coeff_row_id).Bind(2, role).Bind(3, static_cast<int64_t>(i));
        t.Bind(4, m.term_names[i]).Bind(5, i < m.coeffs.size() ? m.coeffs[i] : AnalysisRow::kNaN);
        t.Run();
    }
    Stmt c(db,
           "INSERT INTO coeff_covariance(coeff_row_id, role, row_index, col_index, value) "
           "VALUES (?,?,?,?,?)");
    for (size_t i = 0; i < m.covariance.size(); ++i) {
        for (size_t j = 0; j < m.covariance[i].size(); ++j) {
            c.Bind(1, coeff_row_id).Bind(2, role).Bind(3, static_cast<int64_t>(i));
            c.Bind(4, static_cast<int64_t>(j)).Bind(5, m.covariance[i][j]).Run();
        }
    }
}

}  // namespace

int64_t InsertAnalysisRow(Db& db, const AnalysisRow& r) {
    if (r.sensor_id.empty()) throw StoreError("analysis: sensor_id is empty");
    RequireRun(db, r.run_id, " (an analysis is stored with a recorded run)");
    Stmt s(db, std::string("INSERT INTO analyses(") + kResultOriginColumns +
                   ", verdict, candidates_json, added_json, offset_rms_v_before, "
                   "offset_rms_v_after, rate_rms_dps_before, rate_rms_dps_after, drift_dph_before, "
                   "drift_dph_after, floor_rate_rms_dps, result_json, coeff_row_id, outcome) "
                   "VALUES (?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?)");
    s.BindFrom(BindResultOrigin(s, r), r.verdict, r.candidates_json, r.added_json,
               r.offset_rms_v_before, r.offset_rms_v_after, r.rate_rms_dps_before,
               r.rate_rms_dps_after, r.drift_dph_before, r.drift_dph_after, r.floor_rate_rms_dps,
               r.result_json, r.coeff_row_id, r.outcome);
    s.Run();
    return db.LastInsertRowId();
}

std::string AnalysisSource(int64_t analysis_id) {
    return "analysis:" + std::to_string(analysis_id);
}

std::unique_ptr<Db> OpenForUpdate(const std::string& path) {
    if (IsCentralUrl(path)) {
        throw StoreError("the central database '" + WithoutCredentials(path) +
                         "' is written only by gyrocal push: store results on the station (--db "
                         "FILE) and push them, or do not store them here (--no-store)");
    }
    if (!std::filesystem::exists(path)) {
        throw StoreError("database '" + path + "' does not exist (record a run first)");
    }
    auto db = std::make_unique<Db>(path, Db::Mode::kReadWrite);
    ConfigureConnection(*db);
    Migrate(*db);
    return db;
}

CoeffInsert InsertCoeffSetOnce(Db& db, const CoeffSetRow& r) {
    Stmt find(db,
              "SELECT coeff_row_id FROM coeff_sets WHERE run_id = ? AND sensor_id = ? AND "
              "coeff_set_id = ? AND source = ? ORDER BY coeff_row_id LIMIT 1");
    find.Bind(1, r.run_id).Bind(2, r.sensor_id).Bind(3, r.coeff_set_id).Bind(4, r.source);
    if (find.Step()) return {find.Int(0), false};
    Stmt(db, "INSERT OR IGNORE INTO runs(run_id, first_recv_utime) VALUES (?,?)")
        .Bind(1, r.run_id)
        .Bind(2, r.recv_utime)
        .Run();
    Stmt(db, "INSERT OR IGNORE INTO sensors(sensor_id, first_recv_utime) VALUES (?,?)")
        .Bind(1, r.sensor_id)
        .Bind(2, r.recv_utime)
        .Run();
    Stmt s(db,
           "INSERT INTO coeff_sets(run_id, sensor_id, coeff_set_id, source, utime, recv_utime) "
           "VALUES (?,?,?,?,?,?)");
    s.Bind(1, r.run_id).Bind(2, r.sensor_id).Bind(3, r.coeff_set_id).Bind(4, r.source);
    s.Bind(5, r.utime).Bind(6, r.recv_utime).Run();
    const int64_t id = db.LastInsertRowId();
    InsertModel(db, id, "offset", r.offset);
    InsertModel(db, id, "sensitivity", r.sensitivity);
    Stmt p(db, "INSERT INTO coeff_set_plateaus(coeff_row_id, plateau_id) VALUES (?,?)");
    for (int64_t v : r.plateau_ids) p.Bind(1, id).Bind(2, v).Run();
    Stmt q(db, "INSERT INTO coeff_set_rotations(coeff_row_id, rotation_id) VALUES (?,?)");
    for (int64_t v : r.rotation_ids) q.Bind(1, id).Bind(2, v).Run();
    return {id, true};
}

int64_t InsertAnalysis(Db& db, const AnalysisRow& row) {
    Transaction tx(db);
    const int64_t id = InsertAnalysisRow(db, row);
    tx.Commit();
    return id;
}

int64_t StoreCoeffSet(Db& db, const CoeffSetRow& set) {
    if (set.sensor_id.empty()) throw StoreError("coefficient set: sensor_id is empty");
    if (set.source.empty()) throw StoreError("coefficient set: source is empty");
    CoeffSetRow row = set;
    if (row.recv_utime <= 0) row.recv_utime = WallUtimeNow();
    Transaction tx(db);
    const CoeffInsert r = InsertCoeffSetOnce(db, row);
    tx.Commit();
    return r.coeff_row_id;
}

StoredAnalysis StoreAnalysis(Db& db, const AnalysisRow& row, const CoeffSetRow* extended) {
    if (extended && extended->sensor_id != row.sensor_id) {
        throw StoreError("analysis of sensor '" + row.sensor_id +
                         "': its coefficient set is for sensor '" + extended->sensor_id + "'");
    }
    AnalysisRow a = row;
    if (a.created_wall_utime <= 0) a.created_wall_utime = WallUtimeNow();
    a.coeff_row_id.reset();
    Transaction tx(db);
    StoredAnalysis out;
    out.analysis_id = InsertAnalysisRow(db, a);
    out.source = AnalysisSource(out.analysis_id);
    if (extended) {
        CoeffSetRow set = *extended;
        set.run_id = a.run_id;
        set.source = out.source;
        set.recv_utime = a.created_wall_utime;
        out.coeff_row_id = InsertCoeffSetOnce(db, set).coeff_row_id;
        Stmt(db, "UPDATE analyses SET coeff_row_id = ? WHERE analysis_id = ?")
            .Bind(1, *out.coeff_row_id)
            .Bind(2, out.analysis_id)
            .Run();
    }
    tx.Commit();
    return out;
}

std::vector<AnalysisRow> ListAnalyses(Db& db, const std::string& run_id,
                                      const std::optional<std::string>& sensor_id) {
    RequireRun(db, run_id);
    Stmt s(db,
           "SELECT analysis_id, run_id, sensor_id, created_wall_utime, software_version, "
           "command_line, verdict, candidates_json, added_json, offset_rms_v_before, "
           "offset_rms_v_after, rate_rms_dps_before, rate_rms_dps_after, drift_dph_before, "
           "drift_dph_after, floor_rate_rms_dps, result_json, coeff_row_id, outcome FROM analyses "
           "WHERE run_id = ?1 AND (CAST(?2 AS TEXT) IS NULL OR sensor_id = ?2) "
           "ORDER BY analysis_id");
    s.Bind(1, run_id);
    if (sensor_id) {
        s.Bind(2, *sensor_id);
    } else {
        s.BindNull(2);
    }
    std::vector<AnalysisRow> out;
    while (s.Step()) {
        AnalysisRow a;
        s.Read(0, a.analysis_id, a.run_id, a.sensor_id, a.created_wall_utime, a.software_version,
               a.command_line, a.verdict, a.candidates_json, a.added_json, a.offset_rms_v_before,
               a.offset_rms_v_after, a.rate_rms_dps_before, a.rate_rms_dps_after,
               a.drift_dph_before, a.drift_dph_after, a.floor_rate_rms_dps, a.result_json,
               a.coeff_row_id);
        if (!s.IsNull(18)) a.outcome = s.Text(18);
        out.push_back(std::move(a));
    }
    return out;
}

}  // namespace gyrocal::db
