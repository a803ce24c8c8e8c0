#pragma once
// A small database with known contents, written through the store's own writer:
//   R1 (stop):  sensors S01, S02; plateaus, a rotation, final coefficient sets (+ one earlier)
//   R2 (abort): sensor S01, a second calibration of S01 (offset +1 mV, sensitivity +1 %)
//   R3 (running): sensor S03, nothing fitted yet
//   ''  (no run): a few samples
//   a hostile sensor id with quotes and a comment terminator, with a coefficient set in R1.
//   R2 also has a closed-loop analysis of S01 that stored an extended model (every registry
//   term) with source "analysis:1", after the fitter's set: ExtendedOffset/ExtendedSensitivity.
#include <cmath>
#include <string>
#include <vector>

#include "store/db/analyses.hpp"
#include "store/db/writer.hpp"
#include "tests/lcmtypes/test_model.hpp"
#include "tests/store/row_builders.hpp"

namespace gyrocal::testing {

inline constexpr const char* kHostileSensor = "X\"*/ '; DROP TABLE runs; --";
inline constexpr int64_t kDay = 86400LL * 1000000LL;
inline constexpr int64_t kWall0 = 1767225600LL * 1000000LL;  // 2026-01-01 00:00:00 UTC

inline db::ModelRow PolyModel(const std::string& quantity, std::vector<double> coeffs) {
    db::ModelRow m;
    m.quantity = quantity;
    const std::vector<std::string> names = {"1", "dT", "dT^2", "dT^3"};
    for (size_t i = 0; i < coeffs.size(); ++i) m.term_names.push_back(names[i]);
    m.coeffs = coeffs;
    m.covariance.assign(coeffs.size(), std::vector<double>(coeffs.size(), 0.0));
    for (size_t i = 0; i < coeffs.size(); ++i) m.covariance[i][i] = 4e-10;  // stddev 2e-5
    SetTestModelScalars(m, {.condition_number = 5.0});
    return m;
}

// Offset 2.5 + a*dT + b*dT^2 [V]; sensitivity s0 + s1*dT [V/dps].
inline db::CoeffSetRow Set(const std::string& run, const std::string& sensor, int64_t id,
                           double offset0, double sens0, int64_t recv_utime,
                           std::vector<int64_t> plateaus = {},
                           std::vector<int64_t> rotations = {}) {
    db::CoeffSetRow c;
    c.run_id = run;
    c.sensor_id = sensor;
    c.coeff_set_id = id;
    c.source = "fitter";
    c.utime = id;
    c.offset = PolyModel("offset_v", {offset0, 1e-3, -2e-5});
    c.sensitivity = PolyModel("sensitivity_v_per_dps", {sens0, 1e-6});
    c.plateau_ids = std::move(plateaus);
    c.rotation_ids = std::move(rotations);
    c.recv_utime = recv_utime;
    return c;
}

// The analysis' extended model of S01 in R2: every term of the registry.
inline db::ModelRow ExtendedOffset() {
    db::ModelRow m = PolyModel("offset_v", {2.501, 1e-3, -2e-5, 3e-7});
    for (const char* t : {"dTdt", "heating", "supply", "direction", "warmup(600)"}) {
        m.term_names.push_back(t);
    }
    for (double c : {0.02, 4e-4, 0.01, -3e-4, 5e-3}) m.coeffs.push_back(c);
    m.covariance.assign(m.coeffs.size(), std::vector<double>(m.coeffs.size(), 0.0));
    m.method = "analysis";
    return m;
}
inline db::ModelRow ExtendedSensitivity() {
    db::ModelRow m = PolyModel("sensitivity_v_per_dps", {0.0067 * 1.01, 1e-6});
    m.term_names.push_back("direction");
    m.coeffs.push_back(3e-5);
    m.covariance.assign(3, std::vector<double>(3, 0.0));
    m.method = "analysis";
    return m;
}

inline db::RunEventRow Event(const std::string& run, const std::string& ev,
                             std::vector<std::string> sensors, int64_t recv_utime) {
    db::RunEventRow e = RunEvent(run, ev, std::move(sensors), recv_utime);
    e.utime = 1000;
    e.reason = ev == "abort" ? "operator pressed stop" : "";
    e.software_version = "v1.2.3";
    e.config_json = R"({"setpoints_c":[0,25,50]})";
    e.command_line = "gyrocal calibrate";
    e.host = "lab-pc";
    return e;
}

// When sample `seq` of a sensor was taken: 10 ms apart from utime 1 s.
inline int64_t SampleUtime(int64_t seq) { return 1000000 + seq * 10000; }

inline db::GyroRow Sample(const std::string& run, const std::string& sensor, int64_t seq,
                          int64_t recv_utime) {
    return GyroSample(run, sensor, seq, SampleUtime(seq), recv_utime);
}

// A plateau or rotation of S01 in R1 over its samples first..last.
template <class Row>
Row OverSamples(Row r, int64_t first, int64_t last) {
    r.first_seq = first;
    r.last_seq = last;
    r.n_samples = static_cast<int32_t>(last - first + 1);
    return r;
}

inline void WriteFixture(const std::string& path) {
    db::StoreWriter w(path, {"test", "host", 1});
    std::vector<db::Row> rows;
    // R1, ten days after kWall0.
    const int64_t t1 = kWall0 + 10 * kDay;
    rows.push_back(Event("R1", "start", {"S01", "S02"}, t1));
    for (int64_t s = 0; s < 300; ++s) {
        rows.push_back(Sample("R1", "S01", s, t1 + s));
        rows.push_back(Sample("R1", "S02", s, t1 + s));
    }
    db::PlateauRow p = OverSamples(Plateau("R1", "S01", SampleUtime(0), SampleUtime(99)), 0, 99);
    p.setpoint_c = 25;
    p.temp_mean_c = 25.01;
    p.gyro_mean_v = 2.5;
    p.recv_utime = t1 + 400;
    rows.push_back(p);
    db::SensitivityRow r =
        OverSamples(Rotation("R1", "S01", SampleUtime(100), SampleUtime(199)), 100, 199);
    r.direction = 1;
    r.temp_c = 25;
    r.encoder_angle_deg = 90;
    r.sensitivity_v_per_dps = 0.0067;
    r.recv_utime = t1 + 401;
    rows.push_back(r);
    rows.push_back(Set("R1", "S01", 10, 2.4, 0.0066, t1 + 500, {1000000}, {}));  // superseded
    rows.push_back(Set("R1", "S01", 11, 2.5, 0.0067, t1 + 600, {1000000}, {2000000}));
    rows.push_back(Set("R1", "S02", 11, 2.45, 0.0068, t1 + 600, {}, {}));
    rows.push_back(Set("R1", kHostileSensor, 12, 2.45, 0.0068, t1 + 601, {}, {}));
    for (int64_t k = 0; k < 2; ++k) {  // two heartbeats of one process: the last one counts
        db::StatusRow st;
        st.run_id = "R1";
        st.process = "gyrocal-plateau";
        st.host = "lab-pc";
        st.pid = 42;
        st.state = "running";
        st.received = 100 * (k + 1);
        st.seq_gaps = 7 * k;
        st.rejected = k;
        st.last_reject = k ? "non_finite: temp_c is NaN" : "";
        st.recv_utime = t1 + 650 + k;
        rows.push_back(st);
    }
    rows.push_back(Event("R1", "stop", {"S01", "S02"}, t1 + 700));
    // R2, twenty days after: S01 recalibrated.
    const int64_t t2 = kWall0 + 20 * kDay;
    rows.push_back(Event("R2", "start", {"S01"}, t2));
    rows.push_back(Set("R2", "S01", 21, 2.501, 0.0067 * 1.01, t2 + 10));
    rows.push_back(Event("R2", "abort", {"S01"}, t2 + 20));
    // R3, thirty days after: still running.
    const int64_t t3 = kWall0 + 30 * kDay;
    rows.push_back(Event("R3", "start", {"S03"}, t3));
    rows.push_back(Sample("R3", "S03", 0, t3 + 1));
    // Outside any run.
    for (int64_t s = 0; s < 5; ++s) rows.push_back(Sample("", "S09", s, kWall0 + s));
    db::LossMap losses;
    losses[{"R1", "GYRO_S01"}].seq_gaps = 3;
    losses[{"R1", ""}].queue_drops = 2;
    w.Write(rows, losses);
    // R2: the analysis of S01 and its extended model, stored after the fitter's set.
    db::AnalysisRow a;
    a.run_id = "R2";
    a.sensor_id = "S01";
    a.created_wall_utime = t2 + 30;
    a.software_version = "v1.3.0";
    a.command_line = "gyrocal analyze R2 --publish";
    a.verdict = "added temp_rate";
    a.candidates_json = R"([{"effect":"temp_rate","statistic":52.1,"decision":"added"},)"
                        R"({"effect":"hysteresis","statistic":0.4,"decision":"rejected"}])";
    a.added_json = R"j([{"effect":"temp_rate","term":"dTdt","coefficient":0.02,)j"
                   R"j("stderr":0.001,"unit":"V/(degC/s)"}])j";
    SetErrors(a, {2.1e-4, 4.2e-5}, {0.031, 0.0062}, {95, 21});
    a.floor_rate_rms_dps = 0.0058;
    a.result_json = R"({"sensor_id":"S01","verdict":"added temp_rate"})";
    db::CoeffSetRow ext = Set("R2", "S01", 22, 0, 0, 0);
    ext.offset = ExtendedOffset();
    ext.sensitivity = ExtendedSensitivity();
    db::StoreAnalysis(w.db(), a, &ext);
}

}  // namespace gyrocal::testing
