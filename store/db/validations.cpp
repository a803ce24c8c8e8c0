#include "store/db/validations.hpp"

#include "store/db/query.hpp"

namespace gyrocal::db {

int64_t InsertValidation(Db& db, const ValidationRow& r) {
    if (r.sensor_id.empty()) throw StoreError("validation: sensor_id is empty");
    RequireRun(db, r.run_id, " (a validation is stored with a recorded run)");
    Transaction tx(db);
    Stmt s(db, std::string("INSERT INTO validations(") + kResultOriginColumns +
                   ", model_origin, coeff_row_id, model_run_id, n_bins, offset_rms_v, "
                   "rate_rms_dps, drift_dph, floor_rate_rms_dps, power_on, result_json) "
                   "VALUES (?,?,?,?,?,?,?,?,?,?,?,?,?,?,?)");
    s.BindFrom(BindResultOrigin(s, r), r.model_origin, r.coeff_row_id, r.model_run_id, r.n_bins,
               r.offset_rms_v, r.rate_rms_dps, r.drift_dph, r.floor_rate_rms_dps, r.power_on,
               r.result_json);
    s.Run();
    const int64_t id = db.LastInsertRowId();
    tx.Commit();
    return id;
}

std::vector<ValidationRow> ListValidations(Db& db, const std::string& run_id,
                                           const std::string& sensor_id) {
    Stmt s(db,
           "SELECT validation_id, run_id, sensor_id, created_wall_utime, software_version, "
           "command_line, model_origin, coeff_row_id, coalesce(model_run_id, ''), n_bins, "
           "offset_rms_v, rate_rms_dps, drift_dph, floor_rate_rms_dps, power_on, result_json "
           "FROM validations WHERE run_id = ?1 AND (?2 = '' OR sensor_id = ?2) "
           "ORDER BY validation_id");
    s.Bind(1, run_id).Bind(2, sensor_id);
    std::vector<ValidationRow> out;
    while (s.Step()) {
        ValidationRow r;
        s.Read(0, r.validation_id, r.run_id, r.sensor_id, r.created_wall_utime, r.software_version,
               r.command_line, r.model_origin, r.coeff_row_id, r.model_run_id, r.n_bins,
               r.offset_rms_v, r.rate_rms_dps, r.drift_dph, r.floor_rate_rms_dps, r.power_on,
               r.result_json);
        out.push_back(r);
    }
    return out;
}

}  // namespace gyrocal::db
