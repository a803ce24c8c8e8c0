#include "validations.hpp"

#include <chrono>

#include "query.hpp"

namespace gyrocal::store {

namespace {
int64_t Now() {
    return std::chrono::duration_cast<std::chrono::microseconds>(
               std::chrono::system_clock::now().time_since_epoch())
        .count();
}
}  // namespace

int64_t InsertValidation(Db& db, const ValidationRow& r) {
    if (r.sensor_id.empty()) throw StoreError("validation: sensor_id is empty");
    if (!RunExists(db, r.run_id))
        throw NotFound("no run '" + r.run_id + "' in database '" + db.path() +
                       "' (a validation is stored with a recorded run)");
    Transaction tx(db);
    Stmt s(db,
           "INSERT INTO validations(run_id, sensor_id, created_wall_utime, software_version, "
           "command_line, model_origin, coeff_row_id, model_run_id, n_bins, offset_rms_v, "
           "rate_rms_dps, drift_dph, floor_rate_rms_dps, power_on, result_json) "
           "VALUES (?,?,?,?,?,?,?,?,?,?,?,?,?,?,?)");
    s.Bind(1, r.run_id).Bind(2, r.sensor_id);
    s.Bind(3, r.created_wall_utime > 0 ? r.created_wall_utime : Now());
    s.Bind(4, r.software_version).Bind(5, r.command_line).Bind(6, r.model_origin);
    s.Bind(7, r.coeff_row_id).Bind(8, r.model_run_id).Bind(9, r.n_bins);
    s.Bind(10, r.offset_rms_v).Bind(11, r.rate_rms_dps).Bind(12, r.drift_dph);
    s.Bind(13, r.floor_rate_rms_dps).Bind(14, r.power_on).Bind(15, r.result_json).Run();
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
        r.validation_id = s.Int(0);
        r.run_id = s.Text(1);
        r.sensor_id = s.Text(2);
        r.created_wall_utime = s.Int(3);
        r.software_version = s.Text(4);
        r.command_line = s.Text(5);
        r.model_origin = s.Text(6);
        if (!s.IsNull(7)) r.coeff_row_id = s.Int(7);
        r.model_run_id = s.Text(8);
        r.n_bins = s.Int(9);
        r.offset_rms_v = s.Real(10);
        r.rate_rms_dps = s.Real(11);
        r.drift_dph = s.Real(12);
        r.floor_rate_rms_dps = s.Real(13);
        r.power_on = s.Text(14);
        r.result_json = s.Text(15);
        out.push_back(r);
    }
    return out;
}

}  // namespace gyrocal::store
