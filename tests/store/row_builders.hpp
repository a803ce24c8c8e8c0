#pragma once
// Store rows for the store's and the recorder's tests, as the recorder would store them: the
// identity and the values every test needs are set here once; a test sets what it checks.
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "store/db/analyses.hpp"
#include "store/db/rows.hpp"
#include "tests/lcmtypes/message_headers.hpp"

namespace gyrocal::testing {

// A sample of a unit at rest at 25 degC: 2.5 V, its supply not measured (NaN, no ADC code).
inline db::GyroRow GyroSample(const std::string& run, const std::string& sensor, int64_t seq,
                              int64_t utime, int64_t recv_utime) {
    return {.run_id = run,
            .sensor_id = sensor,
            .utime = utime,
            .seq = seq,
            .gyro_v = 2.5,
            .temp_c = 25,
            .supply_v = std::nan(""),
            .supply_counts = -1,
            .recv_utime = recv_utime};
}

// A model of `quantity` in powers of dT = T - 25 degC ("1", "dT", "dT^2": up to three
// coefficients), its covariance zero: each fixture sets its own uncertainties and fit figures.
inline db::ModelRow PolynomialModel(const std::string& quantity,
                                    const std::vector<double>& coeffs) {
    db::ModelRow m;
    m.quantity = quantity;
    const std::vector<std::string> names = {"1", "dT", "dT^2"};
    for (size_t i = 0; i < coeffs.size(); ++i) m.term_names.push_back(names.at(i));
    m.coeffs = coeffs;
    m.covariance.assign(coeffs.size(), std::vector<double>(coeffs.size(), 0.0));
    return m;
}

// A run event as the sequencer sends it (no setpoint), received when sent.
inline db::RunEventRow RunEvent(const std::string& run, const std::string& event,
                                std::vector<std::string> sensors, int64_t utime) {
    db::RunEventRow e;
    e.run_id = run;
    e.event = event;
    e.sensor_ids = std::move(sensors);
    e.setpoint_c = std::nan("");
    e.utime = utime;
    e.recv_utime = utime;
    return e;
}

// A plateau of `sensor` in `run` over [start_utime, end_utime] [us] (WindowOf: named by its start
// as the processors name it, sent and received at its end), its supply not measured.
inline db::PlateauRow Plateau(const std::string& run, const std::string& sensor,
                              int64_t start_utime, int64_t end_utime) {
    db::PlateauRow p = WindowOf<db::PlateauRow>(sensor, run, start_utime, end_utime);
    p.supply_mean_v = std::nan("");
    return p;
}

// An accepted rotation (sensitivity point), over its window as a plateau is.
inline db::SensitivityRow Rotation(const std::string& run, const std::string& sensor,
                                   int64_t start_utime, int64_t end_utime) {
    db::SensitivityRow s = WindowOf<db::SensitivityRow>(sensor, run, start_utime, end_utime);
    s.accepted = true;
    return s;
}

// A figure of an analysis with the run's declared model (before) and the extended one (after).
struct BeforeAfter {
    double before, after;
};

// Sets an analysis' errors: residual offset RMS [V], rate RMS [deg/s], integrated drift [deg/h].
inline void SetErrors(db::AnalysisRow& a, BeforeAfter offset_rms_v, BeforeAfter rate_rms_dps,
                      BeforeAfter drift_dph) {
    a.offset_rms_v_before = offset_rms_v.before;
    a.offset_rms_v_after = offset_rms_v.after;
    a.rate_rms_dps_before = rate_rms_dps.before;
    a.rate_rms_dps_after = rate_rms_dps.after;
    a.drift_dph_before = drift_dph.before;
    a.drift_dph_after = drift_dph.after;
}

}  // namespace gyrocal::testing
