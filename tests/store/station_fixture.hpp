#pragma once
// A station's SQLite file with rows in EVERY table of the schema, written through the store's own
// writer (as the recorder and `gyrocal analyze|validate` write them), for the central database's
// tests and the push benchmark:
//   runs "<prefix>-R1", "<prefix>-R2", ...: gyro samples of each unit in batches (several
//   gyro_blocks), encoder samples, chamber states (some without air temperature), chamber and
//   turntable orders, plateau states, power states, rates, status, raw events (binary data), three
//   plateaus and two rotations per unit, a superseded and a final coefficient set per unit, noise
//   estimates with their Allan points, fit reports with exclusions and repeatability, losses;
//   an analysis with an extended model in every run, a validation in every run after the first
//   (of the previous run's set: a link across runs); text with tabs, new lines, backslashes,
//   quotes and non-ASCII letters. The last run may be left open.
// Each unit's offset and sensitivity curves differ by a known amount (`unit_offset_v` per unit
// index, `station_offset_v` for the whole station), for the fleet view.
#include <cmath>
#include <string>
#include <vector>

#include "store/db/analyses.hpp"
#include "store/db/validations.hpp"
#include "store/db/writer.hpp"
#include "tests/lcmtypes/test_model.hpp"
#include "tests/store/row_builders.hpp"

namespace gyrocal::testing {

struct StationSpec {
    std::string prefix = "A";  // run ids "<prefix>-R<k>"
    std::vector<std::string> sensors = {"U01", "U02"};
    int runs = 2;
    int64_t samples_per_sensor = 1500;               // per run
    int64_t wall0_utime = 1767225600LL * 1000000LL;  // 2026-01-01 UTC
    bool last_open = false;                          // the last run has no stop yet
    double station_offset_v = 0;                     // added to every unit's offset [V]
    double unit_offset_v = 0.002;                    // unit i's offset is 2.5 + i * this [V]
    std::string unit_model = "myGyro610EB";          // recorded in the run's configuration
};

inline std::string TrickyText(const std::string& what) {
    return what + ": tab\there, new\nline, back\\slash, 'quote' \"dq\", \xc3\xbcml\xc3\xa4ut";
}

inline db::ModelRow StationModel(const std::string& quantity, std::vector<double> coeffs) {
    db::ModelRow m = PolynomialModel(quantity, coeffs);
    for (size_t i = 0; i < coeffs.size(); ++i) m.covariance[i][i] = 1e-10 * (i + 1);
    m.covariance[0][1] = m.covariance[1][0] = 3e-12;
    SetTestModelScalars(m, {.residual_rms = 1.25e-4, .n_points = 6, .condition_number = 7.5});
    m.temp_min_c = -40;
    m.temp_max_c = 85;
    return m;
}

// The run's rows but its analysis and validation, written in batches of `batch` rows.
inline void WriteStationRun(db::StoreWriter& w, const StationSpec& spec, int k, int64_t t0,
                            bool open) {
    const std::string run = spec.prefix + "-R" + std::to_string(k);
    std::vector<db::Row> rows;
    db::RunEventRow start = RunEvent(run, "start", spec.sensors, t0);
    start.software_version = "v9.9.9-test";
    start.config_json = R"({"unit_model":")" + spec.unit_model + R"(","setpoints_c":[-40,25,85]})";
    start.command_line = "gyrocal calibrate --db station.db";
    start.host = spec.prefix + "-host";
    rows.push_back(start);
    w.Write(rows, {});
    rows.clear();
    const int64_t n = spec.samples_per_sensor;
    for (int64_t s = 0; s < n; ++s) {
        const int64_t utime = 1'000'000 + s * 10'000, recv = t0 + 1000 + s * 10;
        const double temp_c = -40 + 125.0 * static_cast<double>(s) / static_cast<double>(n);
        for (size_t u = 0; u < spec.sensors.size(); ++u) {
            db::GyroRow g = GyroSample(run, spec.sensors[u], s, utime, recv);
            g.temp_c = temp_c;
            g.gyro_v = 2.5 + 0.001 * std::sin(0.01 * static_cast<double>(s + u)) + 1e-9 * s;
            g.temp_v = 1.0 + temp_c / 100;
            if (u == 0) {  // an ADC unit
                g.has_adc = true;
                g.gyro_counts = static_cast<int32_t>(s % 4096);
                g.temp_counts = 2000;
                g.supply_counts = 3000;
                g.supply_v = 5.01;
            }
            rows.push_back(g);
            if (s % 10 == 0)
                rows.push_back(db::RateRow{run, spec.sensors[u], utime, s, 0.01 * u, 90.0, temp_c,
                                           2, 0, recv});
        }
        if (s % 5 == 0) {
            rows.push_back(db::EncoderRow{run, "ENC", utime, s / 5, s * 7, 36000, s * 0.07, recv});
            db::ChamberStateRow c{run, utime, s / 5, 1, 25, temp_c, true, "", recv};
            if (s % 50 == 0) c.air_c = std::nan("");
            rows.push_back(c);
        }
        if (rows.size() >= 700) {  // batches as the recorder commits them: several gyro_blocks
            w.Write(rows, {});
            rows.clear();
        }
    }
    rows.push_back(db::ChamberCmdRow{run, run, 5, 1, 25, 3, t0 + 2});
    rows.push_back(db::TurntableCmdRow{run, run, 6, 2, 90, 30, 100, t0 + 3});
    rows.push_back(db::PlateauStateRow{run, spec.sensors[0], 7, "stable", 25, 0.01, 0.02, 120, 0.5,
                                       1, t0 + 4});
    for (const std::string& id : spec.sensors) {
        rows.push_back(db::PowerStateRow{run, id, 8, 1, 500, "rig", t0 + 5});
        db::StatusRow st;
        st.run_id = run;
        st.process = "gyrocal-plateau";
        st.host = spec.prefix + "-host";
        st.pid = 42;
        st.state = "running";
        st.received = n;
        st.extra_json = R"({"windows":3})";
        st.last_reject = TrickyText("reject");
        st.recv_utime = t0 + 6;
        rows.push_back(st);
    }
    rows.push_back(db::RawEventRow{run,
                                   "ODD_CHANNEL",
                                   t0 + 9,
                                   "00ff10090a5c2700",
                                   "unknown_type",
                                   {0, 255, 16, 9, 10, 92, 39, 0, 1}});
    for (size_t u = 0; u < spec.sensors.size(); ++u) {
        const std::string& id = spec.sensors[u];
        const double off =
            2.5 + spec.station_offset_v + spec.unit_offset_v * static_cast<double>(u);
        for (int p = 1; p <= 3; ++p) {
            db::PlateauRow pl = Plateau(run, id, p * 1'000'000, p * 1'000'000 + 600'000);
            pl.setpoint_c = -40 + 60.0 * p;
            pl.temp_mean_c = pl.setpoint_c + 0.01;
            pl.gyro_mean_v = off + 1e-3 * (pl.temp_mean_c - 25);
            pl.n_samples = 6000;
            rows.push_back(pl);
        }
        for (int r = 1; r <= 2; ++r) {
            db::SensitivityRow sp = Rotation(run, id, r * 2'000'000, r * 2'000'000 + 500'000);
            sp.direction = r == 1 ? 1 : -1;
            sp.sensitivity_v_per_dps = 0.0067;
            sp.reject_reason = r == 2 ? TrickyText("why") : "";
            rows.push_back(sp);
        }
        db::CoeffSetRow c;
        c.run_id = run;
        c.sensor_id = id;
        c.source = "fitter";
        c.offset = StationModel("offset_v", {off - 0.001, 1e-3, -2e-6});
        c.sensitivity = StationModel("sensitivity_v_per_dps", {0.0067, 1e-6});
        c.coeff_set_id = 1;
        c.utime = 9'000'000;
        c.plateau_ids = {1'000'000, 2'000'000};
        c.rotation_ids = {2'000'000};
        c.recv_utime = t0 + 20;
        rows.push_back(c);  // superseded by the final set
        c.coeff_set_id = 2;
        c.offset = StationModel("offset_v", {off, 1e-3, -2e-6});
        c.sensitivity = StationModel("sensitivity_v_per_dps", {0.0067 * (1 + 0.001 * u), 1e-6});
        c.plateau_ids = {1'000'000, 2'000'000, 3'000'000};
        c.rotation_ids = {2'000'000, 4'000'000};
        c.recv_utime = t0 + 21;
        rows.push_back(c);
        db::NoiseRow nz{run,
                        id,
                        9'500'000,
                        1800,
                        600,
                        0.01,
                        3,
                        1e-4,
                        1e-5,
                        2e-5,
                        2e-6,
                        3e-7,
                        3e-8,
                        TrickyText("note"),
                        {0.1, 1, 10},
                        {1e-4, 3e-5, 2e-5},
                        {9e-5, 2e-5, 1e-5},
                        {1.1e-4, 4e-5, 3e-5},
                        {100, 10, 1},
                        t0 + 22};
        rows.push_back(nz);
        db::FitReportRow f;
        f.run_id = run;
        f.sensor_id = id;
        f.source = "fitter";
        f.coeff_set_id = 2;
        f.utime = 9'000'001;
        f.is_final = true;
        f.status = "complete";
        f.offset_detail = TrickyText("order 2");
        f.slow_noise_v = 1e-4;
        f.slow_noise_dps = 0.015;
        f.slow_noise_source = "rig";
        f.excluded.push_back({"plateau", 3'000'000, 85, 2.56, 0.01, 0.002, 5.1, 3.5, "outlier"});
        f.repeats.push_back({25, 1'000'000, 3'000'000, 25.0, 25.1, 1, -1, 1e-5, 2e-5, 0.001, 0.002,
                             0.5, "repeatable"});
        f.recv_utime = t0 + 23;
        rows.push_back(f);
    }
    db::LossMap losses;
    losses[{run, "GYRO_" + spec.sensors[0]}].seq_gaps = 3 + k;
    losses[{run, ""}].queue_drops = 1;
    if (!open) rows.push_back(RunEvent(run, "stop", spec.sensors, t0 + 30));
    w.Write(rows, losses);
}

// The analysis of the run's first unit (with its extended model) and, from the second run on, a
// validation of the previous run's final set of that unit on this run.
inline void AnalyseStationRun(db::Db& db, const StationSpec& spec, int k, int64_t t0) {
    const std::string run = spec.prefix + "-R" + std::to_string(k);
    db::AnalysisRow a;
    a.run_id = run;
    a.sensor_id = spec.sensors[0];
    a.created_wall_utime = t0 + 40;
    a.software_version = "v9.9.9-test";
    a.command_line = "gyrocal analyze " + run;
    a.verdict = TrickyText("added temp_rate");
    a.outcome = "explained";
    a.added_json = R"([{"effect":"temp_rate","term":"dTdt","coefficient":0.02}])";
    a.result_json = R"({"outcome":"explained","note":"a\tb"})";
    SetErrors(a, {2e-4, 4e-5}, {0.03, 0.006}, {95, 21});
    db::CoeffSetRow ext;
    ext.sensor_id = spec.sensors[0];
    ext.coeff_set_id = 3;
    ext.utime = 9'900'000;
    ext.offset = StationModel("offset_v", {2.5 + spec.station_offset_v, 1e-3, -2e-6});
    ext.offset.term_names.push_back("dTdt");
    ext.offset.coeffs.push_back(0.02);
    ext.offset.covariance.assign(4, std::vector<double>(4, 0.0));
    ext.sensitivity = StationModel("sensitivity_v_per_dps", {0.0067, 1e-6});
    db::StoreAnalysis(db, a, &ext);
    if (k == 1) return;
    const std::string previous = spec.prefix + "-R" + std::to_string(k - 1);
    db::Stmt s(db,
               "SELECT max(coeff_row_id) FROM coeff_sets WHERE run_id = ? AND sensor_id = ? "
               "AND source = 'fitter'");
    s.Bind(1, previous).Bind(2, spec.sensors[0]);
    s.Step();
    db::ValidationRow v;
    v.run_id = run;
    v.sensor_id = spec.sensors[0];
    v.created_wall_utime = t0 + 41;
    v.model_origin = "run " + previous;
    v.coeff_row_id = s.Int(0);
    v.model_run_id = previous;
    v.n_bins = 12;
    v.offset_rms_v = 1e-4;
    v.rate_rms_dps = 0.02;
    v.drift_dph = 30;
    v.floor_rate_rms_dps = 0.01;
    v.power_on = "rig";
    v.result_json = "{}";
    db::InsertValidation(db, v);
}

inline void WriteStation(const std::string& path, const StationSpec& spec) {
    db::StoreWriter w(path, {"test", spec.prefix + "-host", 1});
    for (int k = 1; k <= spec.runs; ++k) {
        const int64_t t0 = spec.wall0_utime + k * 3600LL * 1000000LL;
        const bool open = spec.last_open && k == spec.runs;
        WriteStationRun(w, spec, k, t0, open);
        AnalyseStationRun(w.db(), spec, k, t0);
    }
}

}  // namespace gyrocal::testing
