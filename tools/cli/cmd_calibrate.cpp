#include "tools/cli/cmd_calibrate.hpp"

#include <unistd.h>

#include <filesystem>
#include <memory>
#include <sstream>
#include <string>

#include "processors/acceptance/limits.hpp"
#include "processors/plot/gnuplot/gnuplot.hpp"
#include "processors/sequencer/procedure.hpp"
#include "producers/sim/config.hpp"
#include "producers/sim/gyro_facts.hpp"
#include "tools/supervisor/supervisor.hpp"

namespace gyrocal::cli {
namespace {

using namespace supervisor;  // the options and the run are the supervisor's

// The recorder would refuse an unwritable database only after every process started; say it
// before anything runs, with what to do.
void CheckWritableDb(const std::string& db) {
    namespace fs = std::filesystem;
    const fs::path path(db);
    const fs::path dir = path.has_parent_path() ? path.parent_path() : fs::path(".");
    if (!fs::is_directory(dir))
        throw CLI::ValidationError(
            "--db",
            "folder '" + dir.string() + "' does not exist: create it or choose another path");
    if (fs::exists(path) ? access(db.c_str(), W_OK) != 0 : access(dir.c_str(), W_OK) != 0)
        throw CLI::ValidationError("--db",
                                   "'" + db + "' is not writable: choose a path you can write");
}

// What gyrocal calibrate does after the run (cmd_report.hpp: AfterCalibration).
void AddAfterRunOptions(CLI::App* cmd, CalibrateOptions& o) {
    cmd->add_option(
        "--limits", o.limits_file,
        "acceptance limits (JSON; docs/report.md): checked before anything starts, recorded with "
        "the run, each unit judged at the end");
    cmd->add_option(
        "--report", o.report_dir,
        "write the run's calibration report (gyrocal report) into this directory at the end "
        "(created if its parent exists)");
}

// The limits and the report come after the run; what would stop them is said before anything runs.
void CheckAfterRunOptions(CalibrateOptions& o, bool has_after_run) {
    namespace fs = std::filesystem;
    for (const auto& [option, value] :
         {std::pair{"--limits", o.limits_file}, std::pair{"--report", o.report_dir}})
        if (!value.empty() && !has_after_run)
            throw CLI::ValidationError(
                option, "needs the store (this launcher was given no acceptance step)");
    if (!o.limits_file.empty()) {
        try {
            o.limits_json = acceptance::ToJson(acceptance::LoadLimitsFile(o.limits_file)).dump();
        } catch (const acceptance::LimitsError& e) {
            throw CLI::ValidationError("--limits", e.what());
        }
    }
    if (o.report_dir.empty()) return;
    fs::path p = fs::absolute(o.report_dir).lexically_normal();
    if (!p.has_filename()) p = p.parent_path();
    if (fs::exists(p) ? !fs::is_directory(p) : !fs::is_directory(p.parent_path()))
        throw CLI::ValidationError(
            "--report", "'" + o.report_dir + "' is not a directory and its parent does not exist");
    if (plot::gnuplot::FindOnPath("gnuplot").empty())
        throw CLI::ValidationError("--report", plot::gnuplot::kGnuplotMissing);
}

// An option whose valid range CLI11 checks and whose help ends with it (", LO..HI"), both from
// the same two numbers.
template <class T>
CLI::Option* AddInRange(CLI::App* cmd, const std::string& name, T& value, const std::string& help,
                        T lo, T hi) {
    std::ostringstream range;
    range << ", " << lo << ".." << hi;
    return cmd->add_option(name, value, help + range.str())->check(CLI::Range(lo, hi));
}

// Where the run happens: source, database, bus, role of this host, procedure, supervision.
void AddPlaceOptions(CLI::App* cmd, CalibrateOptions* o) {
    cmd->add_option("--source", o->source,
                    "sim (simulated rig), csv FILE, lines (stdin), log FILE (lcm-logger file)")
        ->check(CLI::IsMember(SourceNames()))
        ->capture_default_str();
    cmd->add_option("--input", o->input, "input file for --source csv|log")
        ->check(CLI::ExistingFile);
    cmd->add_option("--db", o->db, "SQLite database that records the run")->capture_default_str();
    cmd->add_option("--lcm-url", o->lcm_url, "LCM URL (default: $GYROCAL_LCM_URL or udpm TTL 0)");
    cmd->add_option(
           "--role", o->role,
           "what this host runs: all, or one role of a multi-host lab: producers (rig/source and "
           "sequencer), processors (plateau, rotation, fitter, compensator), recorder (database)")
        ->check(CLI::IsMember({"all", "producers", "processors", "recorder"}))
        ->capture_default_str();
    cmd->add_option(
           "--chamber", o->chamber,
           "chamber number 1..100 of a lab with several chambers on one LCM group: the bus port "
           "is the URL's + chamber - 1 (chamber 1 = the URL as given)")
        ->check(CLI::Range(1, 100))
        ->capture_default_str();
    cmd->add_option(
           "--procedure", o->procedure,
           "sim: sequencer (the sequencer commands the rig) or rig (the rig runs the profile "
           "itself on data time: the same seed gives the same samples, on one host or several)")
        ->check(CLI::IsMember({"sequencer", "rig"}))
        ->capture_default_str();
    AddInRange(cmd, "--max-restarts", o->max_restarts,
               "restarts of one crashed process per run before the run is aborted", 0, 20)
        ->capture_default_str();
    AddInRange(cmd, "--await-peers-s", o->await_peers_s,
               "wall seconds the producers wait to hear every consumer (recorder, processors) "
               "before publishing",
               1.0, 3600.0)
        ->capture_default_str();
}

// The simulated units and the chamber procedure.
void AddRigOptions(CLI::App* cmd, CalibrateOptions* o) {
    cmd->add_option("--sensors", o->sensors, "simulated units in the chamber")
        ->check(CLI::Range(1, 64))
        ->capture_default_str();
    cmd->add_option("--preset", o->preset, "module preset of the simulated units: 610 or 613")
        ->check(CLI::IsMember({"610", "613"}))
        ->capture_default_str();
    cmd->add_option("--seed", o->seed, "seed of the simulated units and noise")
        ->capture_default_str();
    cmd->add_option(
           "--noise-seed", o->noise_seed,
           "seed of the simulated noise alone, 0 = --seed (same units, another realisation)")
        ->capture_default_str();
    cmd->add_option(
           "--plateau-slow-noise-dps", o->plateau_slow_noise_dps,
           "[deg/s] slow noise in a plateau mean that its standard error cannot show (gyro "
           "characterisation), for the fitter's uncertainties; default: the simulated gyro's "
           "for --source sim, each unit's own Allan deviation from the run for measured data")
        ->check(CLI::Range(0.0, 10.0));
    cmd->add_option(
           "--speed", o->speed,
           "simulated seconds per wall second; 0 = auto: no fixed speed, the source (the "
           "simulated rig, a CSV file) runs as fast as every process of the graph keeps up "
           "(flow control; samples batched 16 per message; lcmtypes/flow/README.md)")
        ->check(CLI::Range(0.0, 2000.0))
        ->capture_default_str();
    cmd->add_option("--profile", o->profile, sequencer::ProfilesHelp())
        ->check(CLI::IsMember(sequencer::ProfileNames()))
        ->capture_default_str();
    cmd->add_option("--setpoints-c", o->setpoints_c,
                    "explicit setpoints [degC], overrides --profile")
        ->delimiter(',');
    cmd->add_option("--ramp-rate-c-per-min", o->ramp_rate_c_per_min,
                    "[degC/min] chamber ramp rate ordered by the sequencer, (0, 30] (the simulated "
                    "chamber's own limit caps it); default: the sequencer's")
        ->check(CLI::Range(0.0, 30.0));
    cmd->add_option(
           "--ramp-range-c", o->ramp_range_c,
           "--profile ramp: MIN,MAX [degC]: cool to MIN, then heat to MAX (default -40,85)")
        ->delimiter(',')
        ->expected(2);
    AddInRange(cmd, "--turn-interval-s", o->turn_interval_s,
               "--profile ramp: [s] data time between +90/-90 turn pairs on the move", 10.0, 7200.0)
        ->capture_default_str();
    AddInRange(cmd, "--dwell-s", o->dwell_s,
               "--profile ramp: [s] held at each waypoint once the air is there (the units' dies "
               "lag the air)",
               0.0, 7200.0)
        ->capture_default_str();
    cmd->add_option("--target-offset-dps", o->target_offset_dps,
                    "--profile ramp: [deg/s] stop early once every unit's offset is known to this "
                    "(1 sigma, worst temperature of the range); 0 = no target")
        ->check(CLI::Range(0.0, 100.0))
        ->capture_default_str();
    cmd->add_option(
           "--target-sensitivity-pct", o->target_sensitivity_pct,
           "--profile ramp: [%] stop early once every unit's sensitivity is known to this; "
           "0 = no target")
        ->check(CLI::Range(0.0, 100.0))
        ->capture_default_str();
    cmd->add_option("--effect", o->effects,
                    "switch on an undeclared effect in the rig, NAME=VALUE (repeatable)")
        ->check([](const std::string& v) {
            // The rig's own parser, so that a bad effect is refused here, before any process
            // starts.
            try {
                sim::EffectsConfig effects;
                sim::ParseEffect(effects, v);
                return std::string();
            } catch (const sim::ConfigError& e) {
                return std::string(e.what());
            }
        });
}

// Logs, time limits, the children's extra arguments, what happens after the run.
void AddProcessOptions(CLI::App* cmd, CalibrateOptions* o) {
    cmd->add_option("--log-dir", o->log_dir,
                    "folder for the child processes' logs (default: a new one in $TMPDIR)");
    cmd->add_option("--wall-timeout-s", o->wall_timeout_s,
                    "abort after this many wall seconds (0 = none)")
        ->check(CLI::NonNegativeNumber);
    cmd->add_option(
           "--final-coeffs-wait-s", o->final_coeffs_wait_s,
           "wall seconds to wait for final coefficients (the closed loop's and the ramp's get 60 s "
           "more per unit: their final fits are on every still bin of the run)")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    cmd->add_option("--truth-out", o->truth_out,
                    "where the rig writes its truth sidecar (default: in --log-dir)");
    for (const ChildArgs& c : kChildArgs)
        cmd->add_option("--" + std::string(c.name) + "-arg", (*o).*c.args,
                        std::string("extra argument for ") + c.child)
            ->allow_extra_args(false);
    cmd->add_flag("--quiet", o->quiet, "no progress line");
    AddAfterRunOptions(cmd, *o);
    cmd->footer(
        "Extra arguments take the form --rig-arg=--package-tau-s=60 (with '=').\n"
        "Several hosts: one command per host with --role, the same --lcm-url (ttl=1) and options;\n"
        "start the recorder and processors roles first. A crashed process is restarted (its state\n"
        "recovered) or the run is aborted with the reason: see docs/faults.md.\n"
        "Measured input (--source csv|log) is checked before any process starts: a file whose "
        "header\n"
        "or first 100 rows cannot be replayed is refused with one line (file:line, column, what "
        "is\n"
        "valid), exit 2, no run recorded. A process that ends the run later (a bad row further "
        "down,\n"
        "a crash) has its own error line printed under the abort line and stored as the run's "
        "reason.\n"
        "Exit codes: 0 run completed with coefficients for every sensor, 1 failure (a process "
        "could not\n"
        "start or died; its log is named), 2 bad options or measured input refused before the "
        "start,\n"
        "3 run aborted or incomplete (chamber fault, Ctrl-C, wall-clock limit, missing "
        "coefficients, a\n"
        "source or process that ended the run: its words shown), 4 run completed but a unit did "
        "not\n"
        "pass its --limits (each such unit and limit named).");
}

// The checks across options, after parsing (CLI::ValidationError names the option); completes
// `o` with what the simulated rig tells the fitter.
void CheckCalibrateOptions(CalibrateOptions& o, bool has_after_run) {
    const Source source = ParseSource(o.source);
    if (ReadsInputFile(source) && o.input.empty())
        throw CLI::ValidationError("--input", "is required with --source " + o.source);
    if (source == Source::kSim && !o.input.empty())
        throw CLI::ValidationError("--input", "is only for --source csv|log");
    const auto profile = sequencer::NamedProfile(o.profile);
    const bool ramp = profile && profile->continuous;
    if (ramp && o.procedure == "rig")
        throw CLI::ValidationError("--profile",
                                   "ramp needs --procedure sequencer (the rig's own "
                                   "procedure has plateaus only)");
    if (ramp && source != Source::kSim)
        throw CLI::ValidationError("--profile",
                                   "ramp orders the chamber: only with --source sim "
                                   "(measured data brings its own procedure)");
    if (!ramp &&
        (!o.ramp_range_c.empty() || o.target_offset_dps > 0 || o.target_sensitivity_pct > 0))
        throw CLI::ValidationError("--ramp-range-c/--target-offset-dps/--target-sensitivity-pct",
                                   "only with --profile ramp");
    if (!o.ramp_range_c.empty() && !(o.ramp_range_c[0] < o.ramp_range_c[1]))
        throw CLI::ValidationError("--ramp-range-c", "MIN,MAX needs MIN < MAX");
    if (o.procedure == "rig" && source != Source::kSim)
        throw CLI::ValidationError(
            "--procedure", "rig is the simulated rig's own procedure: only with --source sim");
    try {
        EffectiveLcmUrl(o);
    } catch (const std::invalid_argument& e) {
        throw CLI::ValidationError("--chamber", e.what());
    }
    if (o.role == "all" || o.role == "recorder") CheckWritableDb(o.db);
    CheckAfterRunOptions(o, has_after_run);
    if (source == Source::kSim) {
        const sim::SimulatedGyroFacts facts = sim::FactsOfSimulatedGyros(o.preset);
        o.simulated =
            SimulatedGyros{facts.plateau_slow_noise_dps, facts.nominal_sensitivity_v_per_dps};
    }
}

}  // namespace

void AddCalibrateCommand(CLI::App& app, std::function<int()>& action,
                         supervisor::StoreServices services) {
    auto o = std::make_shared<CalibrateOptions>(CalibrateOptions::Defaults());
    CLI::App* cmd = app.add_subcommand(
        "calibrate",
        "run a whole calibration: rig or measured data, detectors, fitter, compensator, recorder");
    AddPlaceOptions(cmd, o.get());
    AddRigOptions(cmd, o.get());
    AddProcessOptions(cmd, o.get());
    auto store = std::make_shared<supervisor::StoreServices>(std::move(services));
    cmd->callback([o, store, &action] {
        CheckCalibrateOptions(*o, static_cast<bool>(store->after_run));
        action = [o, store] { return RunCalibration(*o, *store); };
    });
}

}  // namespace gyrocal::cli
