#include "tests/support/othersim/cli.hpp"

#include <sstream>
#include <stdexcept>

namespace gyrocal::othersim {

namespace {

std::vector<std::string> Split(const std::string& s, char sep) {
    std::vector<std::string> out;
    std::stringstream ss(s);
    for (std::string item; std::getline(ss, item, sep);) out.push_back(item);
    return out;
}

double Number(const std::string& text, const std::string& what) {
    size_t used = 0;
    double v = 0;
    try {
        v = std::stod(text, &used);
    } catch (const std::exception&) {
        used = 0;
    }
    if (used == 0 || used != text.size() || !std::isfinite(v))
        throw std::invalid_argument(what + ": '" + text + "' is not a number");
    return v;
}

int Index(const std::string& text, const std::string& what) {
    const double v = Number(text, what);
    if (v != static_cast<int>(v) || v < 0)
        throw std::invalid_argument(what + ": '" + text + "' is not an index >= 0");
    return static_cast<int>(v);
}

}  // namespace

Disturbance ParseDisturbance(const std::string& text) {
    const auto f = Split(text, ':');
    if (f.size() != 2 && f.size() != 3 && f.size() != 5)
        throw std::invalid_argument("--disturb '" + text +
                                    "': expected DWELL:VOLTS, DWELL:SENSOR:VOLTS or "
                                    "DWELL:SENSOR:VOLTS:START_S:DURATION_S");
    Disturbance d;
    d.dwell_index = Index(f[0], "--disturb dwell");
    if (f.size() >= 3) d.sensor_id = f[1];
    d.offset_v = Number(f[f.size() == 2 ? 1 : 2], "--disturb volts");
    if (f.size() == 5) {
        d.start_after_s = Number(f[3], "--disturb start");
        d.duration_s = Number(f[4], "--disturb duration");
    }
    return d;
}

Slip ParseSlip(const std::string& text) {
    const auto f = Split(text, ':');
    if (f.size() != 2) throw std::invalid_argument("--slip '" + text + "': expected TURN:DEG");
    return Slip{Index(f[0], "--slip turn"), Number(f[1], "--slip degrees")};
}

void AddOptions(CLI::App& app, Options& o, CliValues& v) {
    app.option_defaults()->always_capture_default();  // --help shows every option's default
    app.add_option("--out", v.out, "CSV file to write (the project's import format)")->required();
    app.add_option("--truth-out", v.truth_out, "truth JSON (default: OUT with .truth.json)");
    app.add_option("--seed", o.seed, "draws the units and the noise");
    app.add_option("--noise-seed", o.noise_seed,
                   "the noise alone (0: --seed): the same units with fresh noise, e.g. a held-out "
                   "record");
    app.add_option("--units", o.units, "units U1..Un, 1..64");
    app.add_option("--id-prefix", o.id_prefix, "sensor id prefix");
    app.add_option("--setpoints-c", v.setpoints, "[degC] chamber setpoints, comma-separated");
    app.add_option("--dwell-s", v.dwell_s, "[s] hold at each setpoint before its turns");
    app.add_flag("--ramp-only", v.ramp_only, "no dwells and no turns: ramps through the setpoints");
    app.add_option("--ramp-c-per-min", o.profile.ramp_c_per_min, "[degC/min] controller ramp");
    app.add_option("--start-c", o.profile.start_c, "[degC] room temperature at power-on");
    app.add_option("--lead-in-s", o.profile.lead_in_s, "[s] powered before the first ramp");
    app.add_option("--tail-s", o.profile.tail_s, "[s] recorded after the last step");
    app.add_option("--turn-deg", o.profile.turn_deg, "[deg] each turn");
    app.add_option("--turn-rate-dps", o.profile.turn_rate_dps, "[deg/s]");
    app.add_option("--turn-accel-dps2", o.profile.turn_accel_dps2, "[deg/s^2]");
    app.add_option("--sample-rate-hz", o.sample_rate_hz, "[Hz]");
    app.add_option("--encoder-counts-per-rev", o.encoder_counts_per_rev, "[count/rev]");
    app.add_option("--chamber-period-s", o.thermal.chamber_period_s, "[s]");
    app.add_option("--chamber-damping", o.thermal.chamber_damping, "< 1 overshoots");
    app.add_option("--board-tau-s", o.thermal.board_tau_s, "[s]");
    app.add_option("--die-tau-s", o.thermal.die_tau_s, "[s]");
    app.add_option("--self-heating-c", o.thermal.self_heating_c, "[degC]");
    app.add_option("--white-dps-rthz", o.noise.white_dps_rthz, "[deg/s/sqrt(Hz)]");
    app.add_option("--flicker-dps", o.noise.flicker_dps, "[deg/s] flat Allan level");
    app.add_option("--rrw-dps-rts", o.noise.rrw_dps_rts, "[deg/s/sqrt(s)]");
    app.add_option("--lpf-hz", o.noise.lpf_hz, "[Hz] each of two poles");
    app.add_option("--adc-bits", o.adc.bits, "0 = unquantised volts");
    app.add_option("--warmup-v", o.effects.warmup_v, "[V] power-on offset transient");
    app.add_option("--gradient-v-per-c", o.effects.gradient_v_per_c,
                   "[V/degC] offset per degC of board-die gradient");
    app.add_option("--supply-v-per-v", o.effects.supply_v_per_v, "[V/V] offset per supply volt");
    app.add_option("--drift-v-per-h", o.effects.drift_v_per_h, "[V/h] offset drift (aging)");
    app.add_option("--periodic-v", o.effects.periodic_v, "[V] periodic offset amplitude");
    app.add_option("--periodic-s", o.effects.periodic_s, "[s] its period");
    app.add_option("--step-v", o.effects.step_v, "[V] offset step");
    app.add_option("--step-at-s", o.effects.step_at_s, "[s] when the step happens");
    app.add_option("--warmup2-v", o.effects.warmup2_v, "[V] second, slow warm-up");
    app.add_option("--warmup2-tau-s", o.effects.warmup2_tau_s, "[s] its time constant");
    app.add_flag("--no-supply", v.no_supply, "leave the supply_v column out");
    app.add_option("--disturb", v.disturb,
                   "DWELL[:SENSOR]:VOLTS[:START_S:DURATION_S] offset shift during that dwell "
                   "(0-based; SENSOR empty = all; default from the dwell's start to its turns), "
                   "repeatable")
        ->default_str("");  // none: "[]" would say nothing
    app.add_option("--slip", v.slip, "TURN:DEG the encoder slips during that turn, repeatable")
        ->default_str("");
}

std::string Finish(Options& o, CliValues& v) {
    try {
        o.profile.steps = ParseSetpoints(v.setpoints, v.ramp_only ? 0.0 : v.dwell_s, !v.ramp_only);
        for (const auto& d : v.disturb) o.faults.disturbances.push_back(ParseDisturbance(d));
        for (const auto& s : v.slip) o.faults.slips.push_back(ParseSlip(s));
    } catch (const std::invalid_argument& e) {
        return e.what();
    }
    o.supply.write = !v.no_supply;
    if (v.truth_out.empty()) {
        const std::string stem = v.out.size() > 4 && v.out.substr(v.out.size() - 4) == ".csv"
                                     ? v.out.substr(0, v.out.size() - 4)
                                     : v.out;
        v.truth_out = stem + ".truth.json";
    }
    return o.Validate();
}

}  // namespace gyrocal::othersim
