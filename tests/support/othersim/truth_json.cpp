// The truth sidecar of an othersim run (generator.hpp: TruthJson).
#include <cmath>

#include "tests/support/othersim/generator.hpp"

namespace gyrocal::othersim {

// The effects under their option names (the phase of the periodic one is not part of the truth).
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(EffectOptions, warmup_v, warmup_tau_s, gradient_v_per_c,
                                   supply_v_per_v, drift_v_per_h, periodic_v, periodic_s, step_v,
                                   step_at_s, warmup2_v, warmup2_tau_s)
// The timeline's spans under their field names (a turn's slip is a fault, its move a detail).
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(DwellSpan, index, setpoint_c, ramp_start_s, start_s,
                                   turns_start_s, end_s)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(TurnSpan, index, dwell_index, start_s, end_s, angle_deg)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(DisturbanceSpan, dwell_index, sensor_id, offset_v, start_s,
                                   end_s)

namespace {

nlohmann::json UnitJson(const UnitTruth& u) {
    nlohmann::json j;
    j["sensor_id"] = u.sensor_id;
    j["offset_v"] = {{"form",
                      "null_v + a1 x + a2 x^2 + a3 x^3 + bend_v exp(-(T + 40)/bend_c), "
                      "x = (T - 25)/50, T die [degC]"},
                     {"null_v", u.null_v},
                     {"a1", u.a1},
                     {"a2", u.a2},
                     {"a3", u.a3},
                     {"bend_v", u.bend_v},
                     {"bend_c", u.bend_c}};
    j["sensitivity_v_per_dps"] = {{"form", "s0 (1 + b1 x + b2 x^2 + b3 x^3)"},
                                  {"s0", u.s0},
                                  {"b1", u.b1},
                                  {"b2", u.b2},
                                  {"b3", u.b3}};
    j["temp_line"] = {{"form", "temp_v = v_at_25c + v_per_c (T_die - 25)"},
                      {"v_at_25c", u.temp_v_at_25c},
                      {"v_per_c", u.temp_v_per_c}};
    j["self_heating_c"] = u.self_heating_c;
    nlohmann::json table = nlohmann::json::array();
    for (int t = -60; t <= 150; ++t)
        table.push_back({{"die_c", t},
                         {"offset_v", u.OffsetV(t)},
                         {"sensitivity_v_per_dps", u.SensitivityVPerDps(t)}});
    j["table"] = table;
    return j;
}

nlohmann::json TimelineJson(const Timeline& tl) {
    return {{"duration_s", tl.duration_s}, {"dwells", tl.dwells}, {"turns", tl.turns}};
}

nlohmann::json FaultsJson(const Timeline& tl) {
    nlohmann::json f = nlohmann::json::array();
    for (const DisturbanceSpan& d : tl.disturbances) {
        nlohmann::json disturbance = d;
        disturbance["kind"] = "disturbance";
        f.push_back(disturbance);
    }
    for (const TurnSpan& s : tl.turns)
        if (s.slip_deg > 0)
            f.push_back({{"kind", "encoder_slip"},
                         {"turn_index", s.index},
                         {"dwell_index", s.dwell_index},
                         {"slip_deg", s.slip_deg},
                         {"start_s", s.slip_start_s},
                         {"end_s", s.slip_end_s}});
    return f;
}

}  // namespace

nlohmann::json TruthJson(const Options& o, const Generated& g) {
    nlohmann::json j;
    j["format"] = "gyrocal-othersim-truth/1";
    j["seed"] = o.seed;
    j["sample_rate_hz"] = o.sample_rate_hz;
    j["rows"] = g.rows;
    j["csv_temp_transfer"] = {
        {"note",
         "the CSV has no temp_c: the importer's default 2.5 V at 25 degC, 9 mV/K maps "
         "temp_v to temp_c; temp_line maps temp_v to the die temperature"}};
    nlohmann::json units = nlohmann::json::array();
    for (const UnitTruth& u : g.units) units.push_back(UnitJson(u));
    j["units"] = units;
    j["noise"] = {{"white_dps_rthz", o.noise.white_dps_rthz},
                  {"flicker_dps", o.noise.flicker_dps},
                  {"rrw_dps_rts", o.noise.rrw_dps_rts},
                  {"lpf_hz", o.noise.lpf_hz},
                  {"adev_dps_at",
                   {{"1", RateNoise::TheoryAdevDps(o.noise, 1)},
                    {"10", RateNoise::TheoryAdevDps(o.noise, 10)},
                    {"100", RateNoise::TheoryAdevDps(o.noise, 100)},
                    {"1000", RateNoise::TheoryAdevDps(o.noise, 1000)}}}};
    j["effects"] = o.effects;
    j["timeline"] = TimelineJson(g.timeline);
    j["faults"] = FaultsJson(g.timeline);
    return j;
}

}  // namespace gyrocal::othersim
