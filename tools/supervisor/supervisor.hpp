#pragma once
// The process graph of one calibration run, started as child processes:
//
//   recorder, plateau detector, rotation estimator, fitter, compensator   (started first; each
//        must send a STATUS heartbeat before anything is published, so no sample is missed)
//   source: the simulated rig (commanded by the sequencer, or running its own procedure) or
//        measured data (CSV file, line stream on stdin, LCM log), for which this launcher itself
//        announces the run
//   sequencer (simulated rig, --procedure sequencer): drives the procedure and ends the run
//
// On several hosts each host runs the part of its role (--role, lab.hpp); the producers wait
// until they hear every consumer's heartbeat over the network. Each launcher supervises its own
// children: one that dies mid-run is restarted with its state recovered, or the run is aborted
// with the reason (the crash policy of lab.hpp); a restart is announced as a RUN_EVENT "restart".
// The launcher's own thread watches the bus (progress, coefficient sets) and the children. On
// completion or Ctrl-C it stops the source first, lets the processors finish, and stops the
// recorder last so it can flush.
#include <functional>
#include <string>
#include <vector>

#include "gyrocal/coeff_set_t.hpp"
#include "gyrocal/plateau_t.hpp"
#include "gyrocal/sensitivity_point_t.hpp"

namespace gyrocal::supervisor {

// What the simulated gyro type tells the fitter for --source sim (the command fills it from the
// rig's side, producers/sim/gyro_facts.hpp, so that running a calibration needs no simulator).
struct SimulatedGyros {
    double plateau_slow_noise_dps = -1.0;        // [deg/s] < 0: not known (not a simulated source)
    double nominal_sensitivity_v_per_dps = 0.0;  // [V/(deg/s)] 0: not known
};

// Where the samples come from (--source): one table of names, parsed once, so that the run
// switches on the kind instead of comparing strings.
enum class Source { kSim, kCsv, kLines, kLog };
struct SourceName {
    const char* name;
    Source source;
};
inline constexpr SourceName kSourceNames[] = {
    {"sim", Source::kSim}, {"csv", Source::kCsv}, {"lines", Source::kLines}, {"log", Source::kLog}};
std::vector<std::string> SourceNames();
// Throws std::invalid_argument naming the valid sources when `name` is none of them.
Source ParseSource(const std::string& name);
// csv and log read a file (--input); sim and lines do not.
inline bool ReadsInputFile(Source s) { return s == Source::kCsv || s == Source::kLog; }

struct CalibrateOptions {
    std::string source = "sim";  // sim | csv | lines | log
    std::string input;           // file for csv and log sources
    std::string db = "gyrocal.db";
    std::string lcm_url;       // "" = $GYROCAL_LCM_URL or the udpm TTL 0 default
    std::string role = "all";  // all | producers | processors | recorder (lab.hpp)
    int chamber = 1;           // 1..100: the bus is the URL's group at port + chamber - 1
    std::string procedure = "sequencer";  // sim: sequencer (commanded rig) | rig (its own profile)
    int max_restarts = 3;        // restarts of one process per run before the run is aborted
    double await_peers_s = 20;   // wall seconds the producers wait for every consumer's heartbeat
    int sensors = 4;             // simulated units
    std::string preset = "610";  // module preset of the simulated units
    uint64_t seed = 1;
    uint64_t noise_seed = 0;  // 0 = seed (see gyrocal-sim-rig --noise-seed)
    // [deg/s] gyrocal-fitter --plateau-slow-noise-dps; < 0 = auto: for the simulated rig its gyro
    // type's characterisation (`simulated`), for measured data the run's
    // own Allan deviation (the fitter's default, NOISE_<id>).
    double plateau_slow_noise_dps = -1.0;
    SimulatedGyros simulated;  // --source sim: the fitter's options for the simulated type
    // Simulated seconds per wall second; 0 = auto: no fixed speed: the simulated rig (--speed 0)
    // and a CSV file (--max) run as fast as every process of the graph keeps up (flow control,
    // lcmtypes/flow), with samples batched kDefaultBatchSamples per message (bus/batch.hpp).
    double speed = 0.0;
    std::string profile = "six";  // sequencer::kDefaultProfile
    std::vector<double> setpoints_c;
    // --profile ramp (sequencer/ramp_procedure.hpp): waypoints MIN,MAX ("" = the profile's),
    // chamber rate, turn interval, dwell at each waypoint, early-stop targets (0 = none).
    std::vector<double> ramp_range_c;
    double ramp_rate_c_per_min = 0.0;  // 0 = the sequencer's default
    double turn_interval_s = 300.0;
    double dwell_s = 300.0;
    double target_offset_dps = 0.0;
    double target_sensitivity_pct = 0.0;
    std::vector<std::string> effects;  // undeclared effects switched on in the rig (NAME=VALUE)
    std::string log_dir;               // child logs; "" = a fresh folder under $TMPDIR
    double wall_timeout_s = 0;         // 0 = none
    double final_coeffs_wait_s = 30;   // wall seconds to wait for the final coefficient sets
    std::string truth_out;             // rig truth sidecar; "" = <log_dir>/truth.json
    std::vector<std::string> rig_args, plateau_args, rotation_args, fitter_args, compensator_args,
        sequencer_args, recorder_args, source_args;  // passed through verbatim
    bool quiet = false;
    std::string command_line;
    std::string limits_file;  // acceptance limits (--limits), recorded in the run's configuration
    std::string limits_json;  // their validated JSON; "" = none
    std::string report_dir;   // write the run's report here at the end (--report); "" = none
    static CalibrateOptions Defaults() { return {}; }
};

// Each child's pass-through arguments, in the order `gyrocal calibrate --help` lists them: the
// child's short name (its option --<name>-arg and its key under "args" in the run's
// configuration), the child as the help names it, and the list in CalibrateOptions.
struct ChildArgs {
    const char* name;
    const char* child;
    std::vector<std::string> CalibrateOptions::*args;
};
inline constexpr ChildArgs kChildArgs[] = {
    {"rig", "gyrocal-sim-rig (repeatable)", &CalibrateOptions::rig_args},
    {"plateau", "gyrocal-plateau", &CalibrateOptions::plateau_args},
    {"rotation", "gyrocal-rotation", &CalibrateOptions::rotation_args},
    {"fitter", "gyrocal-fitter", &CalibrateOptions::fitter_args},
    {"compensator", "gyrocal-compensator", &CalibrateOptions::compensator_args},
    {"sequencer", "gyrocal-sequencer", &CalibrateOptions::sequencer_args},
    {"recorder", "gyrocal-recorder", &CalibrateOptions::recorder_args},
    {"source", "the measured-data source", &CalibrateOptions::source_args}};

// The value gyrocal-fitter gets for --plateau-slow-noise-dps (the auto rule resolved); < 0: none
// is passed and the fitter takes each unit's from the run's Allan deviation.
double EffectivePlateauSlowNoiseDps(const CalibrateOptions& o);

// The LCM URL the run uses: --lcm-url (or $GYROCAL_LCM_URL, or the default) moved to --chamber's
// port. Throws std::invalid_argument naming --chamber.
std::string EffectiveLcmUrl(const CalibrateOptions& o);

// Called once a run has ended and every process (the recorder last) has stopped, so the database
// holds the whole run, with the run id and the exit code so far; returns the exit code (the
// acceptance step: 0 may become 4, a unit did not pass its limits).
using AfterRunHook =
    std::function<int(const CalibrateOptions&, const std::string& run_id, int code)>;

// What a restarted fitter or compensator is given back from the database by the host that holds
// it (lab.hpp): the run's plateaus and sensitivity points, the newest coefficient set of each
// sensor (store/recorder/recovery.hpp reads them).
struct RecoveredState {
    std::vector<plateau_t> plateaus;
    std::vector<sensitivity_point_t> rotations;
    std::vector<coeff_set_t> newest_coeffs;
};
// Throws std::exception with the reason when the database cannot be read.
using RecoveryReader =
    std::function<RecoveredState(const std::string& db_path, const std::string& run_id)>;

// What the supervisor needs of the store, passed in by the caller (the gyrocal command builds
// both from the store's libraries), so that this library links no SQLite. Either may be empty:
// then --limits and --report are refused before the run, and a restarted fitter or compensator
// rebuilds from the live bus only (the launcher says so).
struct StoreServices {
    AfterRunHook after_run;
    RecoveryReader recovery;
};

// Runs the calibration (this host's role of it); returns the exit code (0 completed with
// coefficients for every sensor, 1 failure, 3 run aborted or incomplete; services.after_run
// may turn 0 into 4: a unit did not pass its acceptance limits).
int RunCalibration(const CalibrateOptions& options, const StoreServices& services);

}  // namespace gyrocal::supervisor
