// gyrocal-sequencer: runs the calibration procedure (METHOD.md) over LCM: orders the chamber
// through a temperature profile, waits for every sensor's plateau, orders +90/-90 deg turntable
// moves and waits for the sensitivity points, and publishes the run's start/progress/stop.
// One thread: RunLoop dispatches messages; all decisions are in Procedure (procedure.hpp).
#include <CLI/CLI.hpp>

#include <iostream>
#include <sstream>

#include "bus/channels.hpp"
#include "bus/process_main.hpp"
#include "bus/shutdown.hpp"
#include "sequencer_node.hpp"
#include <nlohmann/json.hpp>

using namespace gyrocal::sequencer;

int main(int argc, char** argv) {
    SequencerOptions o = SequencerOptions::Defaults();
    std::string profile_name = kDefaultProfile;
    std::vector<double> setpoints_c;
    CLI::App app{"gyrocal-sequencer: runs the calibration procedure (chamber setpoints, plateaus, rotations)",
        "gyrocal-sequencer"};
    app.add_option("--lcm-url", o.lcm_url, "LCM URL (default: $GYROCAL_LCM_URL or udpm TTL 0)");
    app.add_option("--profile", profile_name, "named profile: " + ProfilesHelp())
        ->capture_default_str();
    app.add_option("--setpoints-c", setpoints_c, "explicit setpoints [degC], overrides --profile")->delimiter(',');
    app.add_option("--sensors", o.procedure.sensor_ids, "sensor ids to wait for (default: discover from GYRO_*)")
        ->delimiter(',');
    app.add_option("--discover-s", o.discover_s, "[s] data time to discover sensors")->capture_default_str();
    app.add_option("--ramp-rate-c-per-min", o.procedure.ramp_rate_c_per_min, "[degC/min] chamber ramp, (0,30]")
        ->capture_default_str();
    app.add_option("--plateau-timeout-s", o.procedure.plateau_timeout_s,
                   "[s] data time per setpoint before the run aborts as a chamber fault")->capture_default_str();
    app.add_option("--moves-deg", o.procedure.moves_deg, "[deg] turntable moves at each setpoint")
        ->delimiter(',')->capture_default_str();
    app.add_option("--rotation-rate-dps", o.procedure.rotation_rate_dps, "[deg/s] cruise rate")->capture_default_str();
    app.add_option("--rotation-accel-dps2", o.procedure.rotation_accel_dps2, "[deg/s^2]")->capture_default_str();
    app.add_option("--rotation-timeout-s", o.procedure.rotation_timeout_s, "[s] data time per move")
        ->capture_default_str();
    app.add_option("--move-attempts", o.procedure.move_attempts,
                   "orders of one move (a rejected or missing sensitivity point asks again), 1..5")
        ->capture_default_str();
    app.add_option("--retry-wait-s", o.procedure.retry_wait_s,
                   "[s] data time at rest before a move is ordered again, 0..600")
        ->capture_default_str();
    std::vector<double> range_c;
    app.add_option("--ramp-range-c", range_c,
                   "ramp profile: MIN,MAX [degC]; waypoints MIN then MAX (the cooling, then the "
                   "heating ramp), overrides the profile's")
        ->delimiter(',')->expected(2);
    app.add_option("--turn-interval-s", o.procedure.turn_interval_s,
                   "ramp profile: [s] data time between +90/-90 pairs, 10..7200")->capture_default_str();
    app.add_option("--dwell-s", o.procedure.dwell_s,
                   "ramp profile: [s] held at each waypoint once the air is there, 0..7200")
        ->capture_default_str();
    app.add_option("--target-offset-dps", o.procedure.target_offset_dps,
                   "ramp profile: [deg/s] stop early once every unit's offset is known this well "
                   "(1 sigma, whole range); 0 = no target")->capture_default_str();
    app.add_option("--target-sensitivity-pct", o.procedure.target_sensitivity_pct,
                   "ramp profile: [%] stop early once every unit's sensitivity is known this well; "
                   "0 = no target")->capture_default_str();
    app.add_option("--run-id", o.run_id, "run id (default: UTC time-host-pid)");
    app.add_option("--resume-setpoint-index", o.procedure.resume_setpoint_index,
                   "resume run --run-id at this 0-based setpoint (a restarted sequencer; needs "
                   "--run-id and --sensors); -1 = start a new run")
        ->capture_default_str();
    app.add_option("--run-config-json", o.run_config_json, "configuration of the whole process graph, recorded");
    app.add_option("--command-line", o.command_line, "command line to record (default: this one)");
    app.footer("Exit codes: 0 run completed, 1 runtime failure, 2 bad options, 3 run aborted "
               "(chamber fault, operator stop).");
    // Bad options are the frame's (exit 2, "gyrocal-sequencer: <reason>"); the run is not: its
    // exit code is the procedure's (0 completed, 3 aborted), so it is kept here.
    const auto validate = [&]() -> std::string {
        const auto named = NamedProfile(profile_name);
        if (!named) {
            std::string valid;
            for (const auto& n : ProfileNames()) valid += (valid.empty() ? "" : ", ") + n;
            return "--profile: unknown profile '" + profile_name + "': valid are " + valid;
        }
        o.procedure.profile = *named;
        if (!setpoints_c.empty())
            o.procedure.profile = Profile{named->continuous ? named->name : "custom", setpoints_c,
                                          named->continuous};
        if (!named->continuous && (o.procedure.target_offset_dps > 0 || o.procedure.target_sensitivity_pct > 0))
            return "--target-offset-dps/--target-sensitivity-pct: only with --profile ramp (a plateau run "
                   "visits every setpoint)";
        if (!range_c.empty()) {
            if (!named->continuous) return "--ramp-range-c: only with --profile ramp";
            if (!(range_c[0] < range_c[1]))
                return "--ramp-range-c: MIN,MAX needs MIN < MAX (got " + std::to_string(range_c[0]) +
                       "," + std::to_string(range_c[1]) + ")";
            o.procedure.profile.setpoints_c = range_c;
        }
        if (std::string e = gyrocal::channels::SensorIdsProblem(o.procedure.sensor_ids, "--sensors");
            !e.empty())
            return e;
        if (o.procedure.resume_setpoint_index >= 0 && (o.run_id.empty() || o.procedure.sensor_ids.empty()))
            return "--resume-setpoint-index: resuming needs the run's --run-id and --sensors";
        try {
            if (o.procedure.sensor_ids.empty()) {
                ProcedureOptions probe = o.procedure;
                probe.sensor_ids = {"probe"};
                probe.Validate();
            } else {
                o.procedure.Validate();
            }
        } catch (const std::invalid_argument& e) {
            const std::string what = e.what();
            if (what.rfind("resume setpoint index", 0) == 0) return "--resume-setpoint-index: " + what;
            if (what.rfind("move attempts", 0) == 0) return "--move-attempts: " + what;
            if (what.rfind("retry wait", 0) == 0) return "--retry-wait-s: " + what;
            if (what.rfind("turn interval", 0) == 0) return "--turn-interval-s: " + what;
            if (what.rfind("dwell", 0) == 0) return "--dwell-s: " + what;
            if (what.rfind("target offset", 0) == 0) return "--target-offset-dps: " + what;
            if (what.rfind("target sensitivity", 0) == 0) return "--target-sensitivity-pct: " + what;
            return what;
        }
        if (!o.run_config_json.empty() && !nlohmann::json::accept(o.run_config_json))
            return "--run-config-json: is not valid JSON";
        return "";
    };
    if (auto exit_code = gyrocal::ParseCommandLine(app, argc, argv, "gyrocal-sequencer", validate))
        return *exit_code;
    if (o.command_line.empty()) {
        std::ostringstream cl;
        for (int i = 0; i < argc; ++i) cl << (i ? " " : "") << argv[i];
        o.command_line = cl.str();
    }
    try {
        gyrocal::InstallStopHandlers();
        SequencerNode node(o);
        return node.Run();
    } catch (const std::exception& e) {
        std::cerr << "gyrocal-sequencer: " << e.what() << "\n";
        return 1;
    }
}
