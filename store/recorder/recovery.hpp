#pragma once
// What a restarted fitter or compensator needs back, read from the database the recorder wrote,
// as the messages they consume: the run's plateaus and sensitivity points (the fitter's whole
// state is those), and the newest coefficient set of each sensor (what a compensator applies).
// Published again on their usual channels, they rebuild the restarted process; the recorder
// keeps each plateau, point and set once per key, so the database holds no copies.
#include <string>
#include <vector>

#include "gyrocal/coeff_set_t.hpp"
#include "gyrocal/plateau_t.hpp"
#include "gyrocal/sensitivity_point_t.hpp"
#include "store/db/sqlite_db.hpp"

namespace gyrocal::recorder {

struct RecoveredRun {
    std::vector<plateau_t> plateaus;             // in acquisition order
    std::vector<sensitivity_point_t> rotations;  // in acquisition order, rejected ones too
    std::vector<coeff_set_t> newest_coeffs;      // one per sensor
};

// Throws db::NotFound when the run is not in the database, StoreError when it cannot be read.
RecoveredRun ReadRecovery(db::Db& db, const std::string& run_id);

}  // namespace gyrocal::recorder
