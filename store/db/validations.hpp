#pragma once
// Validations stored with the run they validated (table `validations`): a model applied to a run
// it was not fitted on (`gyrocal validate`). SQLite only.
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "store/db/result_origin.hpp"
#include "store/db/sqlite_db.hpp"

namespace gyrocal::db {

// One validation of one sensor of a run (the origin: the validated run and sensor).
struct ValidationRow : ResultOrigin {
    int64_t validation_id = 0;            // set by the database (ignored on insert)
    std::string model_origin;             // where the model came from
    std::optional<int64_t> coeff_row_id;  // the stored set, when it came from this database
    std::string model_run_id;             // the run the model was fitted on, when known
    int64_t n_bins = 0;
    double offset_rms_v = kNaN, rate_rms_dps = kNaN, drift_dph = kNaN;  // [V], [deg/s], [deg/h]
    double floor_rate_rms_dps = kNaN;                                   // [deg/s]
    std::string power_on;     // where time since power-on came from
    std::string result_json;  // the whole result

    static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
};

// Inserts one validation and returns its id. Throws NotFound when the run is not in the
// database, StoreError on an empty sensor id or a write failure.
int64_t InsertValidation(Db& db, const ValidationRow& row);

// The validations of a run (all sensors when sensor_id is ""), oldest first.
std::vector<ValidationRow> ListValidations(Db& db, const std::string& run_id,
                                           const std::string& sensor_id = "");

}  // namespace gyrocal::db
