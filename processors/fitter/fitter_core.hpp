#pragma once
// The fitter's state machine, without the bus.
//
// Per sensor it keeps the points of the current run: plateaus (offset points: gyro_mean_v at
// temp_mean_c, standard error gyro_sem_v with the slow noise added, below) and accepted
// sensitivity points (both rotation directions are points at their own temperatures). A
// RUN_EVENT "start" of a new run clears every sensor and adopts the new run id (a repeated start
// of the current run changes nothing); points of another run are refused. Before any start the
// first run id seen is adopted (a fitter started late, or data replayed without its start).
//
// Fits (fit/calibration_fit.hpp: FitCalibration): outliers are left out by a leave-one-out test and
// named; order on evidence; when the temperatures do not allow a full temperature model, a lower
// order (a line, a mean) is what can be published, marked partial with the reason. During a run a
// set is emitted after each accepted point when its offset model is complete and the set
// differs from the last one emitted. On RUN_EVENT "stop" every sensor with points gets its FINAL
// set, complete or partial: nothing is withheld that could be published, and a FIT_<id> report
// says which it is. The final set's coeff_set_id and utime are the stop event's (the stop is the
// input that made it final), so the store keeps it apart from the sets published mid-run.
// A point of the run that arrives after its stop (on several hosts the stop can overtake the last
// rotation's result) remakes the final sets with it, 1 us later than the previous final ones, so
// the newest set of a unit is always a final one.
// Without any rotation the sensitivity is the nominal value (method "nominal", covariance NaN =
// unknown: partial); rotations that cannot carry a temperature model give a lower order (partial).
//
// Overdispersion (fit.hpp): a unit's few plateaus leave its largest model few dof, so each fit
// pools the evidence of the run's OTHER units, but only of units that agree (fit/pooling.hpp: an
// F test among the OTHER units, so that the unit's own bad point cannot deny it their evidence;
// a unit whose scatter, after its outlier test, still disagrees with them is fitted on its own
// evidence and gives none). A unit's evidence is its chi2 after its outlier test. A unit's pooled
// c can therefore change when another unit gets a point; at "stop" every sensor is refitted twice
// (the first pass settles the evidence, the second publishes).
//
// Slow noise: a plateau's standard error misses the gyro's noise slower than its window. It is
// added in quadrature: the value of --plateau-slow-noise-dps when given (>= 0), else the unit's
// own Allan deviation from NOISE_<id> (fit terms B, K; noise/allan.hpp: SlowNoiseVariance for the
// plateaus' window within the span of the plateaus, widened for the estimate's own scatter:
// slow_noise.hpp). The NOISE used is the newest one not later
// than the unit's newest plateau (the plateau process publishes one just before each plateau),
// so a replay gives the same fits whatever the timing. Which value and where it came from is in
// every report.
#include <cstdint>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "gyrocal/coeff_set_t.hpp"
#include "gyrocal/fit_report_t.hpp"
#include "gyrocal/noise_t.hpp"
#include "gyrocal/plateau_t.hpp"
#include "gyrocal/run_event_t.hpp"
#include "gyrocal/sensitivity_point_t.hpp"
#include "processors/fit/calibration_fit.hpp"
#include "processors/fit/fit.hpp"
#include "processors/model/model.hpp"

namespace gyrocal::fitter {

// A unit's accepted rotations as fit points (temperature, direction, sensitivity, its error).
std::vector<fit::FitPoint> RotationPoints(
    const std::map<int64_t, gyrocal::sensitivity_point_t>& rotations);

struct CoreOptions {
    fit::FitOptions fit;  // shared by offset and sensitivity fits
    fit::OutlierOptions outliers = fit::OutlierOptions::Defaults();
    double pool_alpha = 0.01;         // [1] of the pooling agreement test
    double repeat_tolerance_c = 2.0;  // [degC] a return to a temperature (fit/repeatability.hpp)
    double nominal_sensitivity_v_per_dps = 0.006;  // [V/(deg/s)] ADXRS610 datasheet value
    // [deg/s] slow noise of a plateau mean that its standard error cannot show (see header);
    // < 0: from the run's own Allan deviation (NOISE_<id>); >= 0: this value (0 = none).
    double plateau_slow_noise_dps = -1.0;
    std::string source = "fitter";
    static CoreOptions Defaults() { return {}; }
    std::string Validate() const;  // "" when valid
};

struct Rejection {
    std::string key;     // short reason key for STATUS ("wrong_sensor", "fit_refused", ...)
    std::string detail;  // what, naming the channel/sensor/field
};

struct CoreOutput {
    std::vector<gyrocal::coeff_set_t> publish;   // each on COEFFS_<sensor_id>
    std::vector<gyrocal::fit_report_t> reports;  // each on FIT_<sensor_id>
    std::vector<Rejection> rejections;
};

// What the fitter last concluded for a sensor (for STATUS and tests).
struct SensorSummary {
    size_t n_plateaus = 0;
    size_t n_rotations = 0;
    bool fitted = false;
    bool complete = false;
    size_t excluded = 0;
    std::string text;  // e.g. "offset wls d2 chi2/dof 1.1, sensitivity 3point" or the refusal
    double offset_chi2_per_dof = model::kUnknown;
    double offset_overdispersion = model::kUnknown;  // c applied to the offset fit (fit.hpp)
    double slow_noise_dps = model::kUnknown;         // [deg/s] added to the plateaus' errors
};

class FitterCore {
public:
    explicit FitterCore(CoreOptions options);

    // channel_sensor: the sensor id taken from the channel name the message arrived on.
    CoreOutput OnRunEvent(const gyrocal::run_event_t& event);
    CoreOutput OnPlateau(const gyrocal::plateau_t& plateau, const std::string& channel_sensor);
    CoreOutput OnSensitivity(const gyrocal::sensitivity_point_t& point,
                             const std::string& channel_sensor);
    CoreOutput OnNoise(const gyrocal::noise_t& noise, const std::string& channel_sensor);

    const std::string& run_id() const { return run_id_; }
    std::map<std::string, SensorSummary> Summaries() const;
    int64_t published() const { return published_; }
    int64_t not_accepted_rotations() const { return not_accepted_; }
    int64_t duplicates() const { return duplicates_; }

private:
    struct Evidence {
        double chi2 = 0.0;
        int dof = 0;
    };
    struct SensorState {
        std::map<int64_t, gyrocal::plateau_t> plateaus;  // by plateau_id = acquisition order
        std::map<int64_t, gyrocal::sensitivity_point_t> rotations;  // by rotation_id
        std::map<int64_t, gyrocal::noise_t> noise;                  // by utime
        std::optional<gyrocal::coeff_set_t> last;
        std::string last_refusal;
        SensorSummary summary;
        // This unit's own overdispersion evidence from its latest fits (after exclusions).
        Evidence offset_evidence, sens_evidence;
    };
    struct Refit {
        bool emit = false;   // publish when changed
        bool final = false;  // the run's stop: publish whatever can be published
        int64_t stop_utime = 0;
    };
    // FitCalibration with the pool of the other units; a unit whose own evidence then disagrees
    // with that pool is refitted on its own. `evidence`: what the unit gives the others (its own
    // reference chi2 and dof after the points it lost); `note`: pooling notes.
    fit::CalibrationFit FitPooled(const std::string& id, const std::vector<fit::FitPoint>& points,
                                  bool offset, Evidence& evidence, std::string& note) const;
    // FitOptions with the agreeing other units' overdispersion evidence pooled in.
    fit::FitOptions Pooled(const std::string& sensor_id, bool offset, std::string& note) const;

    // Refits one sensor (fitter_refit.cpp).
    void RefitSensor(const std::string& sensor_id, SensorState& s, const Refit& how,
                     CoreOutput& out);
    // The offset cannot (yet) be published: why, once per change; the final report says so.
    void NotYet(const std::string& sensor_id, SensorState& s, const fit::CalibrationFit& offset,
                const Refit& how, CoreOutput& out);
    // Both passes of the final fits (settle the evidence, then publish), made at `final_utime`.
    void RefitFinal(int64_t final_utime, CoreOutput& out);
    // A point admitted after the run's stop: refit as usual, or remake the final sets.
    void RefitAfterPoint(const std::string& sensor_id, SensorState& s, CoreOutput& out);
    // Common guards; returns false (and adds a rejection) when the message must be skipped.
    bool Admit(const std::string& kind, const std::string& msg_sensor,
               const std::string& channel_sensor, const std::string& msg_run, CoreOutput& out);

    CoreOptions options_;
    std::string run_id_;
    std::set<std::string> run_sensors_;  // sensor_ids declared by the run start; empty = any
    std::map<std::string, SensorState> sensors_;
    std::optional<int64_t> final_utime_;  // [us] of the run's newest final sets, once stopped
    int64_t published_ = 0;
    int64_t not_accepted_ = 0;
    int64_t duplicates_ = 0;
};

}  // namespace gyrocal::fitter
