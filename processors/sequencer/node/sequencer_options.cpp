#include "processors/sequencer/node/sequencer_options.hpp"

#include <memory>
#include <nlohmann/json.hpp>

#include "lcmtypes/channels/channels.hpp"

namespace gyrocal::sequencer::node {
namespace {

// What the options hold before they are resolved into SequencerOptions (the validator's input).
struct Raw {
    std::string profile_name = kDefaultProfile;
    std::vector<double> setpoints_c, range_c;
};

void AddRampOptions(CLI::App& app, SequencerOptions& o, Raw& raw) {
    app.add_option("--ramp-range-c", raw.range_c,
                   "ramp profile: MIN,MAX [degC]; waypoints MIN then MAX (the cooling, then the "
                   "heating ramp), overrides the profile's")
        ->delimiter(',')
        ->expected(2)
        ->default_str("");
    app.add_option("--turn-interval-s", o.procedure.turn_interval_s,
                   "ramp profile: [s] data time between +90/-90 pairs, 10..7200");
    app.add_option("--dwell-s", o.procedure.dwell_s,
                   "ramp profile: [s] held at each waypoint once the air is there, 0..7200");
    app.add_option("--target-offset-dps", o.procedure.target_offset_dps,
                   "ramp profile: [deg/s] stop early once every unit's offset is known this well "
                   "(1 sigma, whole range); 0 = no target");
    app.add_option("--target-sensitivity-pct", o.procedure.target_sensitivity_pct,
                   "ramp profile: [%] stop early once every unit's sensitivity is known this well; "
                   "0 = no target");
}

// The profile from --profile, --setpoints-c and --ramp-range-c; "" or the problem.
std::string ResolveProfile(SequencerOptions& o, const Raw& raw) {
    const auto named = NamedProfile(raw.profile_name);
    if (!named) {
        std::string valid;
        for (const auto& n : ProfileNames()) valid += (valid.empty() ? "" : ", ") + n;
        return "--profile: unknown profile '" + raw.profile_name + "': valid are " + valid;
    }
    o.procedure.profile = *named;
    if (!raw.setpoints_c.empty())
        o.procedure.profile =
            Profile{named->continuous ? named->name : "custom", raw.setpoints_c, named->continuous};
    if (!named->continuous &&
        (o.procedure.target_offset_dps > 0 || o.procedure.target_sensitivity_pct > 0))
        return "--target-offset-dps/--target-sensitivity-pct: only with --profile ramp (a plateau "
               "run "
               "visits every setpoint)";
    if (!raw.range_c.empty()) {
        if (!named->continuous) return "--ramp-range-c: only with --profile ramp";
        if (!(raw.range_c[0] < raw.range_c[1]))
            return "--ramp-range-c: MIN,MAX needs MIN < MAX (got " +
                   std::to_string(raw.range_c[0]) + "," + std::to_string(raw.range_c[1]) + ")";
        o.procedure.profile.setpoints_c = raw.range_c;
    }
    return "";
}

// ProcedureOptions::Validate's message with the option it came from in front.
std::string ValidateProcedure(const SequencerOptions& o) {
    try {
        ProcedureOptions probe = o.procedure;
        if (probe.sensor_ids.empty()) probe.sensor_ids = {"probe"};
        probe.Validate();
    } catch (const std::invalid_argument& e) {
        const std::string what = e.what();
        const std::pair<const char*, const char*> prefixes[] = {
            {"resume setpoint index", "--resume-setpoint-index"},
            {"move attempts", "--move-attempts"},
            {"retry wait", "--retry-wait-s"},
            {"turn interval", "--turn-interval-s"},
            {"dwell", "--dwell-s"},
            {"target offset", "--target-offset-dps"},
            {"target sensitivity", "--target-sensitivity-pct"}};
        for (const auto& [field, option] : prefixes)
            if (what.rfind(field, 0) == 0) return std::string(option) + ": " + what;
        return what;
    }
    return "";
}

std::string Validate(SequencerOptions& o, const Raw& raw) {
    if (std::string e = ResolveProfile(o, raw); !e.empty()) return e;
    if (std::string e = gyrocal::channels::ValidateSensorIds(o.procedure.sensor_ids, "--sensors");
        !e.empty())
        return e;
    if (o.procedure.resume_setpoint_index >= 0 &&
        (o.run_id.empty() || o.procedure.sensor_ids.empty()))
        return "--resume-setpoint-index: resuming needs the run's --run-id and --sensors";
    if (std::string e = ValidateProcedure(o); !e.empty()) return e;
    if (!o.run_config_json.empty() && !nlohmann::json::accept(o.run_config_json))
        return "--run-config-json: is not valid JSON";
    return "";
}

}  // namespace

std::function<std::string()> AddSequencerOptions(CLI::App& app, SequencerOptions& o) {
    auto raw = std::make_shared<Raw>();  // lives as long as the validator
    // --help shows every option's default, but for the lists that start empty: "[]" would say
    // nothing their help does not.
    app.option_defaults()->always_capture_default();
    app.add_option("--lcm-url", o.lcm_url, "LCM URL (default: $GYROCAL_LCM_URL or udpm TTL 0)");
    app.add_option("--profile", raw->profile_name, "named profile: " + ProfilesHelp());
    app.add_option("--setpoints-c", raw->setpoints_c,
                   "explicit setpoints [degC], overrides --profile")
        ->delimiter(',')
        ->default_str("");
    app.add_option("--sensors", o.procedure.sensor_ids,
                   "sensor ids to wait for (default: discover from GYRO_*)")
        ->delimiter(',')
        ->default_str("");
    app.add_option("--discover-s", o.discover_s, "[s] data time to discover sensors");
    app.add_option("--ramp-rate-c-per-min", o.procedure.ramp_rate_c_per_min,
                   "[degC/min] chamber ramp, (0,30]");
    app.add_option("--plateau-timeout-s", o.procedure.plateau_timeout_s,
                   "[s] data time per setpoint before the run aborts as a chamber fault");
    app.add_option("--moves-deg", o.procedure.moves_deg, "[deg] turntable moves at each setpoint")
        ->delimiter(',');
    app.add_option("--rotation-rate-dps", o.procedure.rotation_rate_dps, "[deg/s] cruise rate");
    app.add_option("--rotation-accel-dps2", o.procedure.rotation_accel_dps2, "[deg/s^2]");
    app.add_option("--rotation-timeout-s", o.procedure.rotation_timeout_s,
                   "[s] data time per move");
    app.add_option("--move-attempts", o.procedure.move_attempts,
                   "orders of one move (a rejected or missing sensitivity point asks again), 1..5");
    app.add_option("--retry-wait-s", o.procedure.retry_wait_s,
                   "[s] data time at rest before a move is ordered again, 0..600");
    AddRampOptions(app, o, *raw);
    app.add_option("--run-id", o.run_id, "run id (default: UTC time-host-pid)");
    app.add_option("--resume-setpoint-index", o.procedure.resume_setpoint_index,
                   "resume run --run-id at this 0-based setpoint (a restarted sequencer; needs "
                   "--run-id and --sensors); -1 = start a new run");
    app.add_option("--run-config-json", o.run_config_json,
                   "configuration of the whole process graph, recorded");
    app.add_option("--command-line", o.command_line, "command line to record (default: this one)");
    app.footer(
        "Exit codes: 0 run completed, 1 runtime failure, 2 bad options, 3 run aborted "
        "(chamber fault, operator stop).");
    // Bad options are the frame's (exit 2, "gyrocal-sequencer: <reason>"); the run is not: its
    // exit code is the procedure's (0 completed, 3 aborted), so it is kept here.
    return [&o, raw] { return Validate(o, *raw); };
}

}  // namespace gyrocal::sequencer::node
