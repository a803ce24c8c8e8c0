#pragma once
// The virtual lab: a whole calibration run of the process graph, in one process, on the
// simulated clock. The same pure libraries the processes wrap, wired as the processes wire them:
//
//   Procedure (sequencer) --chamber / turntable orders--> sim::Rig
//   Rig --gyro samples, encoder, chamber state--> per sensor: motion queue -> PlateauDetector
//                                                 per sensor: RotationEstimator (shared encoder
//                                                             MoveDetector)
//   per sensor: the same classified samples -> NoiseTracker (Allan deviation) -> NOISE before
//               each plateau -> FitterCore
//   plateaus, sensitivity points --> FitterCore --> coefficient sets, fit reports
//   plateaus, sensitivity points --> Procedure (which orders the next step)
//   RUN_EVENT orders (start/setpoint/stop) --> detectors, fitter
//
// Delivery is synchronous and in event order: what the bus would deliver a few milliseconds
// later arrives here before the next rig event. Like the plateau process, a gyro sample waits
// until the encoder has reported its moment + the motion guard, then is classified still/moving
// and fed to its detector (so plateaus end a guard interval after their last sample). Procedure
// time advances on every chamber state and gyro scan, as the sequencer's does.
//
// No clock, no LCM runtime (the generated message structs carry plateaus, points and sets, so
// the fitter core is the one the fitter process runs), no randomness of its own: a Run() is a
// deterministic function of its configuration.
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "gyrocal/coeff_set_t.hpp"
#include "gyrocal/fit_report_t.hpp"
#include "gyrocal/noise_t.hpp"
#include "gyrocal/plateau_t.hpp"
#include "gyrocal/sensitivity_point_t.hpp"
#include "processors/fitter/fitter_core.hpp"
#include "processors/fitter/ramp_fitter.hpp"
#include "processors/model/convert.hpp"
#include "processors/motion/table_motion.hpp"
#include "processors/noise/noise_tracker.hpp"
#include "processors/plateau/plateau_detector.hpp"
#include "processors/rotation/rotation_estimator.hpp"
#include "processors/sequencer/procedure.hpp"
#include "producers/sim/rig.hpp"

namespace gyrocal::virtual_lab {

struct LabConfig {
    sim::RigConfig rig = sim::RigConfig::Defaults();
    // sensor_ids empty = every unit of the rig.
    sequencer::ProcedureOptions procedure;
    plateau::PlateauConfig plateau = plateau::PlateauConfig::Defaults();
    motion::MoveDetectorConfig move = motion::MoveDetectorConfig::Defaults();
    double motion_guard_s = motion::kDefaultGuardS;  // [s] as gyrocal-plateau's --motion-guard-s
    double encoder_stale_s = 2.0;                    // [s] as gyrocal-plateau's --encoder-stale-s
    noise::TrackerConfig noise = noise::TrackerConfig::Defaults();  // as gyrocal-plateau's
    rotation::RotationConfig rotation = rotation::RotationConfig::Defaults();
    fitter::CoreOptions fitter = fitter::CoreOptions::Defaults();
    // Continuous (ramp) profiles: the ramp fitter replaces the plateau fitter core.
    fitter::RampFitterOptions ramp_fitter = fitter::RampFitterOptions::Defaults();
    // Plateau profiles: also the fitter's closed loop (gyrocal-fitter --closed-loop, on in the
    // process): at the stop each unit's final set fitted on every still sample, kept in
    // RunResult::closed_loop_sets. Off here by default: the lab's benchmarks compare the plateau
    // methods, whose sets stay in final_sets either way.
    bool closed_loop = false;
    std::string run_id = "virtual-lab";
    double max_sim_s = 24 * 3600.0;  // [s] simulated-time cap: the run is cut (outcome "cut")

    // A lab running the named `profile` (sequencer::ProfileNames()) with the fitter forced to
    // `method`.
    // Throws std::invalid_argument on an unknown profile.
    static LabConfig For(const std::string& profile, fit::Method method);
};

struct RunResult {
    std::string outcome;             // "completed", "abort" (procedure's) or "cut" (max_sim_s)
    std::string outcome_reason;      // the procedure's reason
    std::vector<std::string> notes;  // skipped moves etc. (procedure notes)
    std::vector<gyrocal::plateau_t> plateaus;                      // every plateau, in order
    std::vector<gyrocal::sensitivity_point_t> sensitivity_points;  // every point, accepted or not
    std::vector<gyrocal::coeff_set_t> published;    // every set the fitter core emitted, in order
    std::vector<gyrocal::fit_report_t> reports;     // every report, in order
    std::map<std::string, gyrocal::noise_t> noise;  // the last NOISE of each sensor
    std::map<std::string, model::CoeffSet> final_sets;  // the newest set of each sensor (the
                                                        // fitter core's or the ramp fitter's)
    // LabConfig::closed_loop: each unit's final set of the closed loop and the analysis behind it.
    std::map<std::string, model::CoeffSet> closed_loop_sets;
    std::map<std::string, analysis::SensorResult> closed_loop_results;
    std::map<std::string, analysis::BinSnapshot> closed_loop_bins;  // the still bins it fitted
    std::vector<fitter::Rejection> fitter_rejections;
    std::vector<sim::UnitTruth> truths;  // the rig's units (evaluation only)
    int64_t start_utime = 0;             // [us] first order of the procedure (run start)
    int64_t last_point_utime = 0;        // [us] when the last plateau/point needed arrived
    int64_t end_utime = 0;               // [us] rig time when the run stopped
    // [h] chamber time: from the first order to the last sensitivity point (the run's end).
    double chamber_hours() const {
        return 1e-6 * static_cast<double>(last_point_utime - start_utime) / 3600.0;
    }
    int64_t samples_per_sensor = 0;  // gyro scans simulated
};

// Runs the whole procedure. Throws sim::ConfigError / std::invalid_argument on a bad config.
RunResult Run(const LabConfig& config);

}  // namespace gyrocal::virtual_lab
