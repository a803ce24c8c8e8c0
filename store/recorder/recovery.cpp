#include "recovery.hpp"

#include <algorithm>

#include "model/convert.hpp"
#include "model_rows.hpp"
#include "query.hpp"

namespace gyrocal::record {
namespace {

using namespace gyrocal::store;

plateau_t ToMessage(const PlateauRow& r) {
    plateau_t m;
    m.utime = r.utime;
    m.sensor_id = r.sensor_id;
    m.run_id = r.run_id;
    m.plateau_id = r.plateau_id;
    m.setpoint_c = r.setpoint_c;
    m.start_utime = r.start_utime;
    m.end_utime = r.end_utime;
    m.first_seq = r.first_seq;
    m.last_seq = r.last_seq;
    m.n_samples = r.n_samples;
    m.n_excluded_motion = r.n_excluded_motion;
    m.seq_gaps = r.seq_gaps;
    m.temp_mean_c = r.temp_mean_c;
    m.temp_std_c = r.temp_std_c;
    m.temp_sem_c = r.temp_sem_c;
    m.temp_slope_c_per_min = r.temp_slope_c_per_min;
    m.gyro_mean_v = r.gyro_mean_v;
    m.gyro_std_v = r.gyro_std_v;
    m.gyro_sem_v = r.gyro_sem_v;
    m.temp_mean_v = r.temp_mean_v;
    m.supply_mean_v = r.supply_mean_v;
    return m;
}

sensitivity_point_t ToMessage(const SensitivityRow& r) {
    sensitivity_point_t m;
    m.utime = r.utime;
    m.sensor_id = r.sensor_id;
    m.run_id = r.run_id;
    m.rotation_id = r.rotation_id;
    m.start_utime = r.start_utime;
    m.end_utime = r.end_utime;
    m.first_seq = r.first_seq;
    m.last_seq = r.last_seq;
    m.n_samples = r.n_samples;
    m.direction = static_cast<int8_t>(r.direction);
    m.temp_c = r.temp_c;
    m.encoder_angle_deg = r.encoder_angle_deg;
    m.offset_v = r.offset_v;
    m.offset_stderr_v = r.offset_stderr_v;
    m.integral_v_s = r.integral_v_s;
    m.sensitivity_v_per_dps = r.sensitivity_v_per_dps;
    m.sensitivity_stderr_v_per_dps = r.sensitivity_stderr_v_per_dps;
    m.accepted = r.accepted;
    m.reject_reason = r.reject_reason;
    return m;
}

}  // namespace

RecoveredRun ReadRecovery(Db& db, const std::string& run_id) {
    const RunDetail d = ShowRun(db, run_id);
    RecoveredRun out;
    for (const PlateauRow& p : d.plateaus) out.plateaus.push_back(ToMessage(p));
    for (const SensitivityRow& s : d.sensitivity_points) out.rotations.push_back(ToMessage(s));
    auto by_time = [](const auto& a, const auto& b) { return a.utime < b.utime; };
    std::stable_sort(out.plateaus.begin(), out.plateaus.end(), by_time);
    std::stable_sort(out.rotations.begin(), out.rotations.end(), by_time);
    // The shared conversions (stored rows -> model -> message), as `gyrocal analyze --publish`
    // uses.
    for (const CoeffSetInfo& c : RunNewestCoeffs(db, run_id))
        out.newest_coeffs.push_back(model::ToMsg(ToCoeffSet(c.set)));
    return out;
}

}  // namespace gyrocal::record
