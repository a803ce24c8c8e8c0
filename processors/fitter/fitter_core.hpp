#pragma once
// The fitter's state machine, without the bus.
//
// Per sensor it keeps the points of the current run: plateaus (offset points: gyro_mean_v at
// temp_mean_c, standard error gyro_sem_v) and accepted sensitivity points (both rotation
// directions are points at their own temperatures; the fit runs over all of them). A RUN_EVENT
// "start" of a new run clears every sensor and adopts the new run id (a repeated start of the
// current run changes nothing); points of another run are refused. Before any start the first
// run id seen is adopted (a fitter started late, or data replayed without its start).
// After each accepted point the sensor is refitted; a coefficient set is emitted when a fit is
// possible and differs from the last one emitted, and once more for every sensor with points on
// RUN_EVENT "stop". Without any rotation the sensitivity is the nominal value (method "nominal",
// covariance NaN = unknown); with rotations too few or too close in temperature for a
// temperature model it is their weighted mean (method "mean"). The offset is never guessed: when
// its fit is refused nothing is published and the reason goes to STATUS.
// Overdispersion (fit.hpp): a unit's five plateaus leave its largest model ONE dof, too few to
// estimate by how much the plateaus' standard errors understate their scatter. The units of a run
// share the plateau window, the chamber and the sensor type, so each fit pools the evidence of
// the run's OTHER units (sum of their reference chi2 and dof from their latest fit of the same
// quantity; a unit's own reference depends only on its own points, so there is no circularity).
// A unit's c can therefore change when another unit gets a point; it is settled by the refit of
// every sensor on RUN_EVENT "stop". c is reported in STATUS (the summary text) and in the
// coefficient set's fit notes (model_t has no field for it; residual_rms stays the weighted RMS).
#include <cstdint>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "fit/fit.hpp"
#include "gyrocal/coeff_set_t.hpp"
#include "gyrocal/plateau_t.hpp"
#include "gyrocal/run_event_t.hpp"
#include "gyrocal/sensitivity_point_t.hpp"

namespace gyrocal::fitter {

struct CoreOptions {
    fit::FitOptions fit;                           // shared by offset and sensitivity fits
    double nominal_sensitivity_v_per_dps = 0.006;  // [V/(deg/s)] ADXRS610 datasheet value
    // [deg/s] standard deviation of a plateau mean that its own standard error cannot show: the
    // gyro's slow noise (bias instability, rate random walk) keeps its value through a ~1 minute
    // window, so the window's scatter misses it. Known from an Allan-deviation characterisation
    // of the gyro type (for the simulated rig at its defaults, 0.015 deg/s for 60 s means:
    // sim::SlowNoiseBinVariance). Added in quadrature to each plateau's gyro_sem_v (converted with
    // the nominal sensitivity). 0 = none: then only the overdispersion estimate (fit.hpp) can
    // widen the errors, and a 3-point fit, with no dof, cannot.
    double plateau_slow_noise_dps = 0.0;
    std::string source = "fitter";
    static CoreOptions Defaults() { return {}; }
    std::string Problem() const;  // "" when valid
};

struct Rejection {
    std::string key;     // short reason key for STATUS ("wrong_sensor", "fit_refused", ...)
    std::string detail;  // what, naming the channel/sensor/field
};

struct CoreOutput {
    std::vector<gyrocal::coeff_set_t> publish;  // each on COEFFS_<sensor_id>
    std::vector<Rejection> rejections;
};

// What the fitter last concluded for a sensor (for STATUS and tests).
struct SensorSummary {
    size_t n_plateaus = 0;
    size_t n_rotations = 0;
    bool fitted = false;
    std::string text;  // e.g. "offset wls d2 chi2/dof 1.1, sensitivity 3point" or the refusal
    double offset_chi2_per_dof = model::kUnknown;
    double offset_overdispersion = model::kUnknown;  // c applied to the offset fit (fit.hpp)
};

class FitterCore {
public:
    explicit FitterCore(CoreOptions options);

    // channel_sensor: the sensor id taken from the channel name the message arrived on.
    CoreOutput OnRunEvent(const gyrocal::run_event_t& event);
    CoreOutput OnPlateau(const gyrocal::plateau_t& plateau, const std::string& channel_sensor);
    CoreOutput OnSensitivity(const gyrocal::sensitivity_point_t& point,
                             const std::string& channel_sensor);

    const std::string& run_id() const { return run_id_; }
    std::map<std::string, SensorSummary> Summaries() const;
    int64_t published() const { return published_; }
    int64_t not_accepted_rotations() const { return not_accepted_; }
    int64_t duplicates() const { return duplicates_; }

private:
    struct SensorState {
        std::map<int64_t, gyrocal::plateau_t> plateaus;  // by plateau_id = acquisition order
        std::map<int64_t, gyrocal::sensitivity_point_t> rotations;  // by rotation_id
        std::optional<gyrocal::coeff_set_t> last;
        std::string last_refusal;
        SensorSummary summary;
        // This unit's own overdispersion evidence (reference chi2, dof) from its latest fits.
        double offset_ref_chi2 = 0.0, sens_ref_chi2 = 0.0;
        int offset_ref_dof = 0, sens_ref_dof = 0;
    };
    // FitOptions with the other units' overdispersion evidence pooled in.
    fit::FitOptions Pooled(const std::string& sensor_id, bool offset) const;

    // Refits one sensor; emits when changed (or always when `force`).
    void Refit(const std::string& sensor_id, SensorState& s, bool force, CoreOutput& out);
    // Common guards; returns false (and adds a rejection) when the message must be skipped.
    bool Admit(const std::string& kind, const std::string& msg_sensor,
               const std::string& channel_sensor, const std::string& msg_run, CoreOutput& out);

    CoreOptions options_;
    std::string run_id_;
    std::set<std::string> run_sensors_;  // sensor_ids declared by the run start; empty = any
    std::map<std::string, SensorState> sensors_;
    int64_t published_ = 0;
    int64_t not_accepted_ = 0;
    int64_t duplicates_ = 0;
};

}  // namespace gyrocal::fitter
