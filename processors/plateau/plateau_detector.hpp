#pragma once
// Stability (plateau) detector of ONE sensor: the seed's "watch the Temp output and acquire only
// once it is stable, then average about a minute at 100 Hz", as a state machine fed samples.
//
//   waiting  --window holds window_s of still samples-->  settling
//   settling --criterion held for min_stable_s----------->  averaging
//   averaging--criterion broken (x leave_factor)--------->  settling (window restarts)
//   averaging--average_s of still samples collected----->  done     (emits the plateau)
//   any      --re-arm------------------------------------>  waiting  (window cleared)
// Re-arm: the chamber setpoint changes, a run event "setpoint"/"start"/"stop"/"abort" arrives,
// or (in done, for data without a chamber) the temperature leaves the plateau by rearm_band_c.
//
// Criterion, on the measured temperature over a sliding window of window_s: a straight-line fit
// whose |slope| <= slope_max_c_per_min AND whose scatter about the line <= scatter_max_c. After a
// setpoint change of D degC the temperature must also have moved min_move_fraction*|D| from where
// it was at the change before the criterion may start holding: a sensor lagging its chamber
// looks flat for a while right after the order, and that must not pass for a plateau.
//
// Samples flagged `moving` (the table turned within a guard interval) are neither put in the
// window nor averaged, and do not break the criterion: a rotation is not instability.
//
// A hole is refused, not averaged over: a sequence gap (samples lost on the network) inside the
// averaging window throws the window away (Step::refused says why) and averaging starts again
// at the first sample after the hole, the criterion still holding. A plateau that is emitted
// therefore never has seq_gaps > 0. (Holes in the sliding criterion window are harmless: it
// fits a line through whatever samples it holds.)
//
// Defaults and why (gyro: ~6 mV/(deg/s), noise ~0.05 deg/s/sqrt(Hz) -> ~2 mV rms at 100 Hz;
// temperature line 9 mV/K):
// - slope_max 0.05 degC/min: over the 60 s average the temperature then moves <= 0.05 degC; with
//   an offset drift of ~1 mV/K that is <= 0.05 mV, below the SEM of the gyro mean
//   (2 mV / sqrt(6000/10) ~ 0.08 mV with the LPF costing ~10x in effective samples); and the
//   plateau pairs mean T with mean V of the same window, so a linear drift is consistent anyway.
//   For a first-order lag of time constant tau the slope is (T_final - T)/tau, so the criterion
//   means "within 0.05*tau/min degC of final" (0.25 degC for tau = 5 min).
// - scatter_max 0.2 degC: above the temperature line's own noise (12-bit ADC over 5 V: 1.22 mV =
//   0.136 degC per LSB -> 0.04 degC rms, plus ~1 mV rms line noise -> ~0.11 degC) and below a
//   chamber's control oscillation (+-0.5 degC -> 0.35 degC rms) that it is meant to reject.
// - window_s 90 s: the slope's standard error is sigma*sqrt(12)/(W*sqrt(n)); at the scatter limit
//   sigma = 0.2 degC, W = 90 s, n = 9000: 8.1e-5 degC/s = 0.0049 degC/min, and 0.015 degC/min with
//   10x fewer effective samples: the threshold is > 3 standard errors, so noise neither fakes nor
//   hides a breach.
// - min_stable_s 30 s: a third of the window must pass with the criterion holding, so a single
//   lucky window on a curving trace does not start the average.
// - average_s 60 s: the seed's minute (6000 samples at 100 Hz).
// - rearm_band_c 1 degC: 5x the scatter limit and ~200x the SE of the line's end value.
// - leave_factor 1.5: hysteresis, so noise at the threshold does not abort an average.
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "processors/motion/gyro_sample.hpp"
#include "processors/numeric/line_fit.hpp"
#include "processors/numeric/series_stats.hpp"

namespace gyrocal::plateau {

struct PlateauConfig {
    double window_s = 90;               // [s] sliding window of the criterion
    double slope_max_c_per_min = 0.05;  // [degC/min]
    double scatter_max_c = 0.2;         // [degC] rms about the fitted line
    double min_stable_s = 30;           // [s] criterion held this long before averaging
    double average_s = 60;              // [s] of still samples averaged
    int sem_batches = 20;               // [count] batches for the batch-means SEM
    double rearm_band_c = 1.0;          // [degC] leaving the plateau by more re-arms (done state)
    double min_move_fraction = 0.5;     // [1] of a setpoint change, moved before judging
    double leave_factor = 1.5;          // [1] thresholds x this abort an average
    double state_period_s = 0.5;        // [s] of data time between state reports (2 Hz)
    static PlateauConfig Defaults() { return {}; }
    // "" when valid, else a sentence naming the field and its valid range.
    std::string Validate() const;
};

enum class State { kWaiting, kSettling, kAveraging, kDone };
const char* StateName(State s);

// A gyro sample (the one struct, motion/gyro_sample.hpp) with what the detector needs beside it.
struct Sample : motion::GyroSample {
    double temp_v = 0;    // [V] temperature sensor output
    bool moving = false;  // table moved within the guard interval
};

// The sample of a gyro reading: anything whose fields are named as gyro_sample_t's (the
// message, the simulator's reading). Its motion is decided later (MotionClassifier).
template <class Gyro>
Sample SampleOf(const Gyro& g) {
    return Sample{motion::GyroSampleOf(g), g.temp_v};
}

struct Plateau {
    std::string run_id;
    int64_t plateau_id = 0;  // [us] = start_utime
    double setpoint_c = std::numeric_limits<double>::quiet_NaN();
    int64_t start_utime = 0, end_utime = 0;
    int64_t first_seq = 0, last_seq = 0;
    int32_t n_samples = 0, n_excluded_motion = 0, seq_gaps = 0;
    numeric::MeanStats temp_c, gyro_v;
    double temp_slope_c_per_min = 0;
    double temp_mean_v = 0;
    double supply_mean_v = std::numeric_limits<double>::quiet_NaN();
};

struct StateReport {
    int64_t utime = 0;
    State state = State::kWaiting;
    double temp_c = 0;
    double temp_slope_c_per_min = std::numeric_limits<double>::quiet_NaN();
    double temp_std_c = std::numeric_limits<double>::quiet_NaN();
    double stable_for_s = 0;
    double averaging_progress = 0;
    int64_t last_plateau_id = -1;
};

struct Step {
    std::optional<StateReport> state;    // set at most every state_period_s and on state changes
    std::optional<Plateau> plateau;      // set when an averaging window completes
    std::optional<std::string> refused;  // an averaging window thrown away, and why
};

class PlateauDetector {
public:
    explicit PlateauDetector(const PlateauConfig& config);  // throws invalid_argument if invalid

    // One sample, utime increasing (the caller guards order and finiteness).
    Step Feed(const Sample& s);

    // CHAMBER_STATE: re-arms when the setpoint differs from the one in force (NaN = unknown).
    void SetChamberSetpoint(double setpoint_c);
    // RUN_EVENT "setpoint": always re-arms; setpoint NaN keeps the chamber's.
    void OnSetpointEvent(double setpoint_c);
    // RUN_EVENT "start" (run id stamped on plateaus) and "stop"/"abort" (cleared); both re-arm.
    void StartRun(const std::string& run_id);
    void EndRun();
    // A detector that joined a run late (restarted mid-run) learns its id: no re-arm.
    void AdoptRun(const std::string& run_id) { run_id_ = run_id; }

    State state() const { return state_; }
    const std::string& run_id() const { return run_id_; }

private:
    void Rearm(double setpoint_change_c);
    void Enter(State s);
    bool CriterionHolds(const numeric::LineFit& fit, double factor) const;
    // Feed's state steps: settling until the criterion has held long enough, then averaging
    // the still samples until average_s of them (the plateau, in `step`).
    void Settle(const Sample& s, const numeric::LineFit& fit);
    void Average(const Sample& s, const Sample& prev, bool had_prev, const numeric::LineFit& fit,
                 Step& step);
    Plateau Finish();
    StateReport Report(int64_t utime, const numeric::LineFit& fit) const;
    // The averaging window's refusal when `s` follows a sequence gap; the window restarts at s.
    std::optional<std::string> RefuseHole(const Sample& s);

    PlateauConfig config_;
    State state_ = State::kWaiting;
    bool state_changed_ = true;
    std::string run_id_;
    double setpoint_c_ = std::numeric_limits<double>::quiet_NaN();
    numeric::SlidingLine window_;
    std::optional<int64_t> stable_since_;
    int64_t last_report_utime_ = 0;
    bool have_report_ = false;
    bool have_sample_ = false;
    Sample last_{};
    // Setpoint-change guard: temperature at the change, and the distance still required.
    std::optional<double> move_ref_c_;
    double move_needed_c_ = 0;
    // Averaging window.
    struct Acc {
        std::vector<double> t_s, temp_c, gyro_v, temp_v, supply_v;
        int64_t start_utime = 0, end_utime = 0, first_seq = 0, last_seq = 0;
        int64_t prev_seq = 0;
        bool any = false, seen_seq = false;
        int32_t excluded = 0, gaps = 0;
        int64_t still_us = 0;  // [us] sum of intervals between consecutive still samples
    } acc_;
    int64_t last_plateau_id_ = -1;
    double last_plateau_temp_c_ = 0;
};

}  // namespace gyrocal::plateau
