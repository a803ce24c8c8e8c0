#pragma once
// The process graph of one calibration run, started as child processes:
//
//   recorder, plateau detector, rotation estimator, fitter, compensator   (started first; each
//        must send a STATUS heartbeat before anything is published, so no sample is missed)
//   source: the simulated rig (commanded by the sequencer) or measured data (CSV file, line
//        stream on stdin, LCM log), for which this launcher itself announces the run
//   sequencer (simulated rig only): drives the procedure and ends the run
//
// The launcher's own thread watches the bus (progress, coefficient sets) and the children (a
// child that dies early fails the run with its log named). On completion or Ctrl-C it stops the
// source first, lets the processors finish, and stops the recorder last so it can flush.
#include <string>
#include <vector>

namespace gyrocal::cli {

inline constexpr double kAutoRigMessagesPerS = 15000.0;

// The slow noise (bias instability, rate random walk) in a plateau mean of `average_s` of the
// simulated gyro type at the rig's default noise settings: what an Allan-deviation
// characterisation of that gyro type tells the fitter (not a unit's truth).
double PlateauSlowNoiseOfSimulatedGyroDps(double average_s = 60.0);

struct CalibrateOptions {
    std::string source = "sim";   // sim | csv | lines | log
    std::string input;            // file for csv and log sources
    std::string db = "gyrocal.db";
    std::string lcm_url;          // "" = $GYROCAL_LCM_URL or the udpm TTL 0 default
    int sensors = 4;              // simulated units
    std::string preset = "610";   // module preset of the simulated units
    uint64_t seed = 1;
    uint64_t noise_seed = 0;      // 0 = seed (see gyrocal-sim-rig --noise-seed)
    // [deg/s] gyrocal-fitter --plateau-slow-noise-dps; < 0 = auto: for the simulated rig its gyro
    // type's characterisation (PlateauSlowNoiseOfSimulatedGyroDps), for measured data the run's
    // own Allan deviation (the fitter's default, NOISE_<id>).
    double plateau_slow_noise_dps = -1.0;
    // Simulated seconds per wall second; 0 = auto: the rig publishes (units + 1 encoder) x 100
    // messages per simulated second, and the whole graph on the 2-core development machine lost
    // nothing at 15000 rig messages/s (4 units at speed 30: 0 lost at load ~6) but 1-2 % at
    // 30000/s (speed 60: ~4200 of 290000 samples per channel lost at load ~9), so auto keeps
    // the rig at 15000 messages/s.
    double speed = 0.0;
    std::string profile = "six";  // sequencer::kDefaultProfile
    std::vector<double> setpoints_c;
    std::vector<std::string> effects;  // undeclared effects switched on in the rig (NAME=VALUE)
    std::string log_dir;          // child logs; "" = a fresh folder under $TMPDIR
    double wall_timeout_s = 0;    // 0 = none
    double final_coeffs_wait_s = 30;  // wall seconds to wait for the final coefficient sets
    std::string truth_out;        // rig truth sidecar; "" = <log_dir>/truth.json
    std::vector<std::string> rig_args, plateau_args, rotation_args, fitter_args, compensator_args,
        sequencer_args, recorder_args, source_args;  // passed through verbatim
    bool quiet = false;
    std::string command_line;
    static CalibrateOptions Defaults() { return {}; }
};

// The value gyrocal-fitter gets for --plateau-slow-noise-dps (the auto rule resolved); < 0: none
// is passed and the fitter takes each unit's from the run's Allan deviation.
double EffectivePlateauSlowNoiseDps(const CalibrateOptions& o);

// Runs the calibration; returns the exit code (0 completed with coefficients for every sensor,
// 1 failure, 3 run aborted or incomplete).
int RunCalibration(const CalibrateOptions& options);

}  // namespace gyrocal::cli
