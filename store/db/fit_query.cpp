#include "store/db/fit_query.hpp"

namespace gyrocal::db {

namespace {

void ReadExclusionsAndRepeats(Db& db, FitReportInfo& info) {
    Stmt x(db,
           "SELECT kind, item_id, temp_c, value, residual, residual_sigma, statistic, threshold, "
           "reason FROM fit_exclusions WHERE fit_report_row_id = ? ORDER BY rowid");
    x.Bind(1, info.fit_report_row_id);
    while (x.Step())
        info.report.excluded.push_back({x.Text(0), x.Int(1), x.Real(2), x.Real(3), x.Real(4),
                                        x.Real(5), x.Real(6), x.Real(7), x.Text(8)});
    Stmt q(db,
           "SELECT temp_c, first_plateau_id, second_plateau_id, first_temp_c, second_temp_c, "
           "first_approach, second_approach, offset_diff_v, offset_diff_stderr_v, "
           "offset_diff_dps, offset_diff_stderr_dps, z, verdict FROM repeatability "
           "WHERE fit_report_row_id = ? ORDER BY rowid");
    q.Bind(1, info.fit_report_row_id);
    while (q.Step())
        info.report.repeats.push_back({q.Real(0), q.Int(1), q.Int(2), q.Real(3), q.Real(4),
                                       static_cast<int32_t>(q.Int(5)),
                                       static_cast<int32_t>(q.Int(6)), q.Real(7), q.Real(8),
                                       q.Real(9), q.Real(10), q.Real(11), q.Text(12)});
}

FitReportInfo ReadFitReport(const Stmt& s) {
    FitReportInfo info;
    FitReportRow& r = info.report;
    s.Read(0, info.fit_report_row_id, r.run_id, r.sensor_id, r.coeff_set_id, r.source, r.utime,
           r.is_final, r.status, r.reason, r.offset_detail, r.sensitivity_detail, r.slow_noise_v,
           r.slow_noise_dps, r.slow_noise_source, r.recv_utime);
    return info;
}

NoiseInfo ReadNoise(const Stmt& s) {
    NoiseInfo info;
    NoiseRow& n = info.noise;
    s.Read(0, info.noise_row_id, n.run_id, n.sensor_id, n.utime, n.still_s, n.n_segments,
           n.longest_segment_s, n.tau0_s, n.arw_v_rthz, n.arw_stderr_v_rthz, n.bias_instability_v,
           n.bias_instability_stderr_v, n.rrw_v_rts, n.rrw_stderr_v_rts, n.fit_note, n.recv_utime,
           info.sensitivity_v_per_dps);
    return info;
}

// The Allan points of an estimate, by tau.
void ReadAdev(Db& db, NoiseInfo& info) {
    Stmt p(db,
           "SELECT tau_s, adev_v, adev_lo_v, adev_hi_v, edf FROM noise_adev "
           "WHERE noise_row_id = ? ORDER BY tau_s");
    p.Bind(1, info.noise_row_id);
    while (p.Step()) {
        info.noise.tau_s.push_back(p.Real(0));
        info.noise.adev_v.push_back(p.Real(1));
        info.noise.adev_lo_v.push_back(p.Real(2));
        info.noise.adev_hi_v.push_back(p.Real(3));
        info.noise.edf.push_back(p.Real(4));
    }
}

}  // namespace

std::vector<FitReportInfo> RunFitReports(Db& db, const std::string& run_id) {
    std::vector<FitReportInfo> out = SelectAll(
        db,
        "SELECT fit_report_row_id, run_id, sensor_id, coeff_set_id, source, utime, is_final, "
        "status, reason, offset_detail, sensitivity_detail, slow_noise_v, slow_noise_dps, "
        "slow_noise_source, recv_utime FROM v_fit_final WHERE run_id = ? "
        "ORDER BY sensor_id, source",
        run_id, ReadFitReport);
    for (FitReportInfo& info : out) ReadExclusionsAndRepeats(db, info);
    return out;
}

std::vector<NoiseInfo> RunNoise(Db& db, const std::string& run_id) {
    std::vector<NoiseInfo> out = SelectAll(
        db,
        "SELECT noise_row_id, run_id, sensor_id, utime, still_s, n_segments, longest_segment_s, "
        "tau0_s, arw_v_rthz, arw_stderr_v_rthz, bias_instability_v, bias_instability_stderr_v, "
        "rrw_v_rts, rrw_stderr_v_rts, fit_note, recv_utime, sensitivity_v_per_dps "
        "FROM v_noise WHERE run_id = ? ORDER BY sensor_id",
        run_id, ReadNoise);
    for (NoiseInfo& info : out) ReadAdev(db, info);
    return out;
}

}  // namespace gyrocal::db
