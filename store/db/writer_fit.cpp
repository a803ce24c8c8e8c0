// StoreWriter: the fitter's reports and the units' noise estimates (schema v5). Few rows per run,
// so the statements are prepared per call (no effect on the sample path's rate).
#include <limits>

#include "store/db/analyses.hpp"
#include "store/db/writer.hpp"

namespace gyrocal::db {

void StoreWriter::WriteNoise(const NoiseRow& r) {
    Stmt s(*db_,
           "INSERT INTO noise_estimates(run_id, sensor_id, utime, still_s, n_segments, "
           "longest_segment_s, tau0_s, arw_v_rthz, arw_stderr_v_rthz, bias_instability_v, "
           "bias_instability_stderr_v, rrw_v_rts, rrw_stderr_v_rts, fit_note, recv_utime) "
           "VALUES (?,?,?,?,?,?,?,?,?,?,?,?,?,?,?)");
    s.Bind(1, r.run_id).Bind(2, r.sensor_id).Bind(3, r.utime).Bind(4, r.still_s);
    s.Bind(5, r.n_segments).Bind(6, r.longest_segment_s).Bind(7, r.tau0_s);
    s.Bind(8, r.arw_v_rthz).Bind(9, r.arw_stderr_v_rthz).Bind(10, r.bias_instability_v);
    s.Bind(11, r.bias_instability_stderr_v).Bind(12, r.rrw_v_rts).Bind(13, r.rrw_stderr_v_rts);
    s.Bind(14, r.fit_note).Bind(15, r.recv_utime).Run();
    const int64_t row = db_->LastInsertRowId();
    Stmt p(*db_,
           "INSERT INTO noise_adev(noise_row_id, tau_s, adev_v, adev_lo_v, adev_hi_v, edf) "
           "VALUES (?,?,?,?,?,?)");
    for (size_t i = 0; i < r.tau_s.size(); ++i) {
        auto at = [&](const std::vector<double>& v) {
            return i < v.size() ? v[i] : std::numeric_limits<double>::quiet_NaN();
        };
        p.Bind(1, row).Bind(2, r.tau_s[i]).Bind(3, at(r.adev_v)).Bind(4, at(r.adev_lo_v));
        p.Bind(5, at(r.adev_hi_v)).Bind(6, at(r.edf)).Run();
    }
}

void StoreWriter::WriteFitReport(const FitReportRow& r) {
    Stmt s(*db_,
           "INSERT INTO fit_reports(run_id, sensor_id, coeff_set_id, source, utime, is_final, "
           "status, reason, offset_detail, sensitivity_detail, slow_noise_v, slow_noise_dps, "
           "slow_noise_source, recv_utime) VALUES (?,?,?,?,?,?,?,?,?,?,?,?,?,?)");
    s.Bind(1, r.run_id).Bind(2, r.sensor_id).Bind(3, r.coeff_set_id).Bind(4, r.source);
    s.Bind(5, r.utime).Bind(6, r.is_final ? 1 : 0).Bind(7, r.status).Bind(8, r.reason);
    s.Bind(9, r.offset_detail).Bind(10, r.sensitivity_detail).Bind(11, r.slow_noise_v);
    s.Bind(12, r.slow_noise_dps).Bind(13, r.slow_noise_source).Bind(14, r.recv_utime).Run();
    const int64_t row = db_->LastInsertRowId();
    Stmt x(*db_,
           "INSERT INTO fit_exclusions(fit_report_row_id, kind, item_id, temp_c, value, residual, "
           "residual_sigma, statistic, threshold, reason) VALUES (?,?,?,?,?,?,?,?,?,?)");
    for (const FitExclusionRow& e : r.excluded) {
        x.Bind(1, row).Bind(2, e.kind).Bind(3, e.item_id).Bind(4, e.temp_c).Bind(5, e.value);
        x.Bind(6, e.residual).Bind(7, e.residual_sigma).Bind(8, e.statistic);
        x.Bind(9, e.threshold).Bind(10, e.reason).Run();
    }
    Stmt q(*db_,
           "INSERT INTO repeatability(fit_report_row_id, run_id, sensor_id, temp_c, "
           "first_plateau_id, second_plateau_id, first_temp_c, second_temp_c, first_approach, "
           "second_approach, offset_diff_v, offset_diff_stderr_v, offset_diff_dps, "
           "offset_diff_stderr_dps, z, verdict) VALUES (?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?)");
    for (const RepeatabilityRow& e : r.repeats) {
        q.Bind(1, row).Bind(2, r.run_id).Bind(3, r.sensor_id).Bind(4, e.temp_c);
        q.Bind(5, e.first_plateau_id).Bind(6, e.second_plateau_id).Bind(7, e.first_temp_c);
        q.Bind(8, e.second_temp_c).Bind(9, e.first_approach).Bind(10, e.second_approach);
        q.Bind(11, e.offset_diff_v).Bind(12, e.offset_diff_stderr_v).Bind(13, e.offset_diff_dps);
        q.Bind(14, e.offset_diff_stderr_dps).Bind(15, e.z).Bind(16, e.verdict).Run();
    }
}

}  // namespace gyrocal::db

namespace gyrocal::db {

// The fitter's closed loop: one analyses row per message, linked to the set it made when that set
// is stored (the fitter publishes the set first, so it is in this batch or an earlier one).
void StoreWriter::WriteClosedLoop(const ClosedLoopRow& r) {
    AnalysisRow a;
    a.run_id = r.run_id;
    a.sensor_id = r.sensor_id;
    a.created_wall_utime = r.recv_utime;
    a.software_version = info_.recorder_version;
    a.command_line = "gyrocal-fitter closed loop (sets of source " + r.source + ", " +
                     (r.is_final ? "final" : "during the run") + ")";
    a.verdict = r.headline;
    a.outcome = r.outcome;
    a.candidates_json = r.candidates_json;
    a.added_json = r.added_json;
    a.offset_rms_v_before = r.offset_rms_v_before;
    a.offset_rms_v_after = r.offset_rms_v_after;
    a.rate_rms_dps_before = r.rate_rms_dps_before;
    a.rate_rms_dps_after = r.rate_rms_dps_after;
    a.drift_dph_before = r.drift_dph_before;
    a.drift_dph_after = r.drift_dph_after;
    a.floor_rate_rms_dps = r.floor_rate_rms_dps;
    a.result_json = r.result_json;
    if (r.coeff_set_id >= 0) {
        Stmt find(*db_,
                  "SELECT coeff_row_id FROM coeff_sets WHERE run_id = ? AND sensor_id = ? AND "
                  "coeff_set_id = ? AND source = ? ORDER BY coeff_row_id LIMIT 1");
        find.Bind(1, r.run_id).Bind(2, r.sensor_id).Bind(3, r.coeff_set_id).Bind(4, r.source);
        if (find.Step()) a.coeff_row_id = find.Int(0);
    }
    InsertAnalysisRow(*db_, a);
}

}  // namespace gyrocal::db
