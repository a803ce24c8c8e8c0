#include "tests/store/runreport/report_fixture.hpp"

#include <cmath>

#include "store/db/analyses.hpp"
#include "store/db/writer.hpp"
#include "tests/store/row_builders.hpp"

namespace gyrocal::testing {

namespace {

double Poly(const std::vector<double>& c, double temp_c) {
    const double d = temp_c - 25.0;
    double v = 0, p = 1;
    for (double x : c) v += x * p, p *= d;
    return v;
}

db::ModelRow Model(const std::string& quantity, const std::vector<double>& c,
                   const std::string& method) {
    db::ModelRow m = PolynomialModel(quantity, c);
    for (size_t i = 0; i < c.size(); ++i) m.covariance[i][i] = std::pow(1e-3 * std::abs(c[i]), 2);
    m.t0_c = 25;
    m.temp_min_c = -40;
    m.temp_max_c = 85;
    m.residual_rms = 3e-5;
    m.n_points = static_cast<int32_t>(kPlateauTemps.size());
    m.condition_number = 4.2;
    m.method = method;
    return m;
}

db::RunEventRow Event(const std::string& ev, int64_t utime) {
    db::RunEventRow e;
    e.run_id = kRunId;
    e.utime = utime;
    e.event = ev;
    e.reason = ev == "stop" ? "end of data" : "";
    e.setpoint_c = NAN;
    e.sensor_ids = {"S01", "S02"};
    e.software_version = "v9.9-fixture";
    e.config_json = std::string(R"({"source":"csv","input":"/lab/run7.csv","input_sha256":")") +
                    std::string(64, 'a') +
                    R"(","plateau_slow_noise_dps":0.01,"acceptance_limits":)" + kLimitsJson +
                    R"(,"acceptance_limits_file":"/lab/limits.json"})";
    e.command_line =
        "gyrocal calibrate --source csv --input /lab/run7.csv --limits /lab/limits.json";
    e.host = "daq-pc";
    e.recv_utime = utime;
    return e;
}

}  // namespace

void WriteReportDb(const std::string& path) {
    db::StoreWriter w(path, {"v9.9-recorder", "analysis-pc", 1});
    std::vector<db::Row> rows;
    const int64_t t0 = 1'000'000'000'000'000;
    const int64_t hour = 3'600'000'000;
    rows.push_back(Event("start", t0));
    db::CoeffSetRow set;
    set.run_id = kRunId;
    set.sensor_id = "S01";
    set.source = "fitter";
    set.coeff_set_id = t0 + 9 * hour;
    set.utime = set.coeff_set_id;
    set.offset = Model("offset_v", kOffset, "wls");
    set.sensitivity = Model("sensitivity_v_per_dps", kSens, "wls");
    set.recv_utime = t0 + 9 * hour;
    for (size_t i = 0; i < kPlateauTemps.size(); ++i) {
        const int64_t start = t0 + static_cast<int64_t>(i + 1) * hour;
        db::PlateauRow p = Plateau(kRunId, "S01", start, start + 60'000'000);
        p.setpoint_c = kPlateauTemps[i];
        p.temp_mean_c = kPlateauTemps[i];
        p.n_samples = 6000;
        p.gyro_sem_v = kSemV;
        const double sigma = std::hypot(kSemV, kSlowNoiseDps * Poly(kSens, p.temp_mean_c));
        p.gyro_mean_v = Poly(kOffset, p.temp_mean_c) + kResidualSigmas[i] * sigma;
        rows.push_back(p);
        set.plateau_ids.push_back(p.plateau_id);
        for (int dir : {+1, -1}) {
            const int64_t turn = p.end_utime + (dir > 0 ? 1 : 2) * 10'000'000;
            db::SensitivityRow s = Rotation(kRunId, "S01", turn, turn + 5'000'000);
            s.direction = dir;
            s.temp_c = kPlateauTemps[i];
            s.encoder_angle_deg = 90.0 * dir;
            s.sensitivity_v_per_dps = Poly(kSens, s.temp_c) * (1 + 1e-4 * dir);
            s.sensitivity_stderr_v_per_dps = 1e-5;
            s.accepted = !(i == 2 && dir < 0);
            if (!s.accepted) s.reject_reason = kRefusal;
            rows.push_back(s);
            if (s.accepted) set.rotation_ids.push_back(s.rotation_id);
        }
    }
    rows.push_back(set);
    for (int i = 0; i < 2; ++i) {
        const int64_t start = t0 + (i + 1) * hour + 5;
        db::PlateauRow p = Plateau(kRunId, "S02", start, start + 60'000'000);
        p.temp_mean_c = kPlateauTemps[i];
        p.gyro_mean_v = 2.49;
        p.gyro_sem_v = kSemV;
        rows.push_back(p);
    }
    for (const char* process : {"gyrocal-fitter", "gyrocal-plateau"}) {
        db::StatusRow st;
        st.run_id = kRunId;
        st.process = process;
        st.host = std::string(process) == "gyrocal-fitter" ? "analysis-pc" : "daq-pc";
        st.pid = 7;
        st.state = "running";
        st.received = 1000;
        st.rejected = 1;
        st.last_reject = "fit_refused: S02 has 2 temperatures";
        st.recv_utime = t0 + 9 * hour;
        rows.push_back(st);
    }
    rows.push_back(Event("stop", t0 + 10 * hour));
    db::LossMap losses;
    losses[{kRunId, "GYRO_S01"}].seq_gaps = 4;
    w.Write(rows, losses);

    db::AnalysisRow a;
    a.run_id = kRunId;
    a.sensor_id = "S01";
    a.created_wall_utime = 1767225600LL * 1000000LL;
    a.software_version = "v9.9-analysis";
    a.command_line = "gyrocal analyze R7";
    a.verdict = "missing effect: supply";
    a.outcome = "partly explained";
    a.candidates_json =
        R"([{"effect":"supply","term":"supply","statistic":61.5,"cv_gain":0.2,"decision":"added"}])";
    a.added_json =
        R"([{"effect":"supply","term":"supply","coefficient":0.004,"stderr":0.0002,"unit":"V/V"}])";
    SetErrors(a, {2e-4, 5e-5}, {0.035, 0.009}, {80, 20});
    a.floor_rate_rms_dps = 0.006;
    a.result_json = R"({"could_not_test":["warmup: the run is shorter than 10 tau"],)"
                    R"("expected_after":{"offset_rms_v":4.5e-5,"rate_rms_dps":0.008}})";
    db::CoeffSetRow ext = set;
    ext.offset.term_names.push_back("supply");
    ext.offset.coeffs.push_back(0.004);
    for (auto& row : ext.offset.covariance) row.push_back(0.0);
    ext.offset.covariance.push_back({0.0, 0.0, 0.0, 4e-8});
    ext.offset.method = "analysis";
    db::StoreAnalysis(w.db(), a, &ext);
}

}  // namespace gyrocal::testing
