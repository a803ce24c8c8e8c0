#include "store/recorder/recovery.hpp"

#include <algorithm>

#include "processors/model/convert.hpp"
#include "store/db/model_rows.hpp"
#include "store/db/query.hpp"
#include "store/recorder/message_fields.hpp"

namespace gyrocal::recorder {

using namespace gyrocal::db;

RecoveredRun ReadRecovery(Db& db, const std::string& run_id) {
    const RunDetail d = ShowRun(db, run_id);
    RecoveredRun out;
    for (const PlateauRow& p : d.plateaus) CopyFields(out.plateaus.emplace_back(), p);
    for (const SensitivityRow& s : d.sensitivity_points)
        CopyFields(out.rotations.emplace_back(), s);
    auto by_time = [](const auto& a, const auto& b) { return a.utime < b.utime; };
    std::stable_sort(out.plateaus.begin(), out.plateaus.end(), by_time);
    std::stable_sort(out.rotations.begin(), out.rotations.end(), by_time);
    // The shared conversions (stored rows -> model -> message), as `gyrocal analyze --publish`
    // uses.
    for (const CoeffSetInfo& c : RunNewestCoeffs(db, run_id))
        out.newest_coeffs.push_back(model::ToMsg(ToCoeffSet(c.set)));
    return out;
}

}  // namespace gyrocal::recorder
