#include "tests/support/othersim/options.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace gyrocal::othersim {

double EffectOptions::OutsideV(double t_s) const {
    return drift_v_per_h * t_s / 3600.0 +
           periodic_v * std::sin(6.283185307179586 * t_s / periodic_s + periodic_phase_rad) +
           (t_s >= step_at_s ? step_v : 0.0) + warmup2_v * std::exp(-t_s / warmup2_tau_s);
}

namespace {

bool In(double v, double lo, double hi) { return std::isfinite(v) && v >= lo && v <= hi; }

std::string Range(const std::string& option, double lo, double hi, const std::string& unit) {
    std::ostringstream os;
    os << option << " must be in [" << lo << ", " << hi << "]" << (unit.empty() ? "" : " " + unit);
    return os.str();
}

std::string ProfileProblem(const ProfileOptions& p) {
    if (p.steps.empty()) return "--setpoints-c: at least one setpoint is needed";
    for (size_t i = 0; i < p.steps.size(); ++i) {
        const Step& s = p.steps[i];
        if (!In(s.setpoint_c, -60, 150))
            return "--setpoints-c: item " + std::to_string(i + 1) + " must be in [-60, 150] degC";
        if (!In(s.dwell_s, 0, 86400)) return Range("--dwell-s", 0, 86400, "s");
    }
    if (!In(p.start_c, -60, 150)) return Range("--start-c", -60, 150, "degC");
    if (!In(p.lead_in_s, 0, 86400)) return Range("--lead-in-s", 0, 86400, "s");
    if (!In(p.ramp_c_per_min, 0.01, 30)) return Range("--ramp-c-per-min", 0.01, 30, "degC/min");
    if (!In(p.turn_deg, 1, 720)) return Range("--turn-deg", 1, 720, "deg");
    if (!In(p.turn_rate_dps, 1, 250)) return Range("--turn-rate-dps", 1, 250, "deg/s");
    if (!In(p.turn_accel_dps2, 1, 2000)) return Range("--turn-accel-dps2", 1, 2000, "deg/s^2");
    if (!In(p.pause_between_turns_s, 0.5, 600) || !In(p.rest_after_turns_s, 0.5, 600))
        return "pauses around the turns must be in [0.5, 600] s";
    if (!In(p.tail_s, 0, 86400)) return Range("--tail-s", 0, 86400, "s");
    return "";
}

std::string PhysicsProblem(const Options& o) {
    const ThermalOptions& t = o.thermal;
    if (!In(t.chamber_period_s, 10, 3600)) return Range("--chamber-period-s", 10, 3600, "s");
    if (!In(t.chamber_damping, 0.1, 2)) return Range("--chamber-damping", 0.1, 2, "");
    if (!In(t.air_wander_c, 0, 2) || !In(t.air_wander_tau_s, 1, 3600))
        return "air wander must be in [0, 2] degC with a correlation time in [1, 3600] s";
    if (!In(t.board_tau_s, 1, 3600)) return Range("--board-tau-s", 1, 3600, "s");
    if (!In(t.die_tau_s, 0.5, 3600)) return Range("--die-tau-s", 0.5, 3600, "s");
    if (!In(t.self_heating_c, 0, 10)) return Range("--self-heating-c", 0, 10, "degC");
    if (!In(t.temp_line_tau_s, 0, 60)) return Range("temp_line_tau_s", 0, 60, "s");
    const NoiseOptions& n = o.noise;
    if (!In(n.white_dps_rthz, 0, 1)) return Range("--white-dps-rthz", 0, 1, "deg/s/sqrt(Hz)");
    if (!In(n.flicker_dps, 0, 1)) return Range("--flicker-dps", 0, 1, "deg/s");
    if (!In(n.rrw_dps_rts, 0, 0.01)) return Range("--rrw-dps-rts", 0, 0.01, "deg/s/sqrt(s)");
    if (!In(n.lpf_hz, 1, 0.45 * o.sample_rate_hz))
        return "--lpf-hz must be in [1, 0.45 x --sample-rate-hz] Hz";
    if (!In(n.temp_line_noise_v, 0, 0.1)) return Range("temp_line_noise_v", 0, 0.1, "V");
    if (o.adc.bits != 0 && (o.adc.bits < 8 || o.adc.bits > 24))
        return "--adc-bits must be 0 (no ADC) or 8..24";
    if (!In(o.adc.vref_v, 1, 10) || !In(o.adc.divider, 0.1, 1) || !In(o.adc.supply_divider, 0.1, 1))
        return "ADC reference must be in [1, 10] V and dividers in [0.1, 1]";
    if (!In(o.supply.nominal_v, 3, 6) || !In(o.supply.wander_v, 0, 0.5) ||
        !In(o.supply.wander_tau_s, 1, 1e5) || !In(o.supply.read_noise_v, 0, 0.1))
        return "supply: nominal 3..6 V, wander 0..0.5 V over 1..1e5 s, read noise 0..0.1 V";
    if (!In(o.effects.warmup_v, -0.1, 0.1) || !In(o.effects.warmup_tau_s, 1, 1e5) ||
        !In(o.effects.gradient_v_per_c, -0.1, 0.1) || !In(o.effects.supply_v_per_v, -1, 1))
        return "effects: warm-up |V| <= 0.1 over 1..1e5 s, gradient |V/degC| <= 0.1, supply |V/V| "
               "<= 1";
    const EffectOptions& e = o.effects;
    if (!In(e.drift_v_per_h, -0.1, 0.1)) return Range("--drift-v-per-h", -0.1, 0.1, "V/h");
    if (!In(e.periodic_v, -0.1, 0.1)) return Range("--periodic-v", -0.1, 0.1, "V");
    if (!In(e.periodic_s, 1, 1e5)) return Range("--periodic-s", 1, 1e5, "s");
    if (!In(e.periodic_phase_rad, -10, 10)) return Range("periodic_phase_rad", -10, 10, "rad");
    if (!In(e.step_v, -0.1, 0.1)) return Range("--step-v", -0.1, 0.1, "V");
    if (!In(e.step_at_s, 0, 1e6)) return Range("--step-at-s", 0, 1e6, "s");
    if (!In(e.warmup2_v, -0.1, 0.1)) return Range("--warmup2-v", -0.1, 0.1, "V");
    if (!In(e.warmup2_tau_s, 1, 1e5)) return Range("--warmup2-tau-s", 1, 1e5, "s");
    return "";
}

std::string FaultProblem(const Options& o) {
    const std::vector<std::string> ids = o.SensorIds();
    for (const Disturbance& d : o.faults.disturbances) {
        if (d.dwell_index < 0 || d.dwell_index >= static_cast<int>(o.profile.steps.size()))
            return "--disturb: dwell " + std::to_string(d.dwell_index) + " is not a step (0.." +
                   std::to_string(o.profile.steps.size() - 1) + ")";
        bool known = d.sensor_id.empty();
        for (const std::string& id : ids) known = known || id == d.sensor_id;
        if (!known) return "--disturb: sensor '" + d.sensor_id + "' is not one of the units";
        if (!In(d.offset_v, -1, 1)) return "--disturb: offset must be in [-1, 1] V";
        if (!In(d.start_after_s, 0, 86400) || !std::isfinite(d.duration_s))
            return "--disturb: start must be in [0, 86400] s and the duration finite";
    }
    int turns = 0;
    for (const Step& s : o.profile.steps) turns += s.turns ? 2 : 0;
    for (const Slip& s : o.faults.slips) {
        if (s.turn_index < 0 || s.turn_index >= turns)
            return "--slip: turn " + std::to_string(s.turn_index) +
                   " is not a turn of the run (0.." + std::to_string(turns - 1) + ")";
        if (!In(s.slip_deg, 0.001, 0.5 * o.profile.turn_deg))
            return "--slip: slip must be in (0, half the turn] deg";
    }
    return "";
}

}  // namespace

Options Options::ReturnToStart(double dwell_s) {
    Options o;
    o.profile.steps = ParseSetpoints("25,-10,10,30,50,70,25", dwell_s, true);
    return o;
}

Options Options::QuickReturnToStart(double dwell_s) {
    Options o = ReturnToStart(dwell_s);
    o.sample_rate_hz = 20.0;
    o.noise.lpf_hz = 8.0;
    o.thermal.board_tau_s = 40.0;
    o.thermal.die_tau_s = 8.0;
    o.thermal.chamber_period_s = 120.0;
    o.profile.ramp_c_per_min = 8.0;
    return o;
}

std::vector<std::string> Options::SensorIds() const {
    std::vector<std::string> ids;
    for (int i = 1; i <= units; ++i) ids.push_back(id_prefix + std::to_string(i));
    return ids;
}

std::string Options::Validate() const {
    if (units < 1 || units > 64) return "--units must be 1..64";
    if (id_prefix.empty() || id_prefix.size() > 20) return "--id-prefix must be 1..20 characters";
    for (char c : id_prefix)
        if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != '-')
            return "--id-prefix may hold letters, digits, '-' and '_' only";
    if (!In(sample_rate_hz, 5, 2000)) return Range("--sample-rate-hz", 5, 2000, "Hz");
    if (!In(encoder_counts_per_rev, 360, 1e7))
        return Range("--encoder-counts-per-rev", 360, 1e7, "");
    if (std::string p = ProfileProblem(profile); !p.empty()) return p;
    if (std::string p = PhysicsProblem(*this); !p.empty()) return p;
    return FaultProblem(*this);
}

std::vector<Step> ParseSetpoints(const std::string& list, double dwell_s, bool turns) {
    std::vector<Step> steps;
    std::stringstream ss(list);
    std::string item;
    int index = 0;
    while (std::getline(ss, item, ',')) {
        ++index;
        size_t used = 0;
        double v = NAN;
        try {
            v = std::stod(item, &used);
        } catch (const std::exception&) {
            used = 0;
        }
        if (used == 0 || used != item.size() || !In(v, -60, 150))
            throw std::invalid_argument("--setpoints-c: item " + std::to_string(index) + " '" +
                                        item + "' is not a temperature in -60..150 degC");
        steps.push_back(Step{v, dwell_s, turns});
    }
    if (steps.empty()) throw std::invalid_argument("--setpoints-c: empty list");
    return steps;
}

}  // namespace gyrocal::othersim
