#include "tests/support/othersim/generator.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <ostream>
#include <stdexcept>

namespace gyrocal::othersim {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kRailLowV = 0.25, kRailHighV = 4.75;

// Independent streams for the chamber, the supply, the encoder and each unit's noise.
uint64_t Stream(uint64_t seed, uint64_t k) { return seed * 0xD1B54A32D192ED03ull + 7919 * k + 1; }

void AddTurns(const ProfileOptions& p, int dwell, double& t, std::vector<TurnSpan>& turns) {
    for (double sign : {1.0, -1.0}) {
        TurnSpan s;
        s.index = static_cast<int>(turns.size());
        s.dwell_index = dwell;
        s.move = Move{sign * p.turn_deg, p.turn_rate_dps, p.turn_accel_dps2};
        s.angle_deg = s.move.angle_deg;
        s.start_s = t;
        s.end_s = t + s.move.Duration();
        turns.push_back(s);
        t = s.end_s + (sign > 0 ? p.pause_between_turns_s : p.rest_after_turns_s);
    }
}

void ApplyFaults(const Options& o, Timeline& tl) {
    for (const Slip& slip : o.faults.slips) {
        TurnSpan& s = tl.turns[static_cast<size_t>(slip.turn_index)];
        s.slip_deg = slip.slip_deg;
        s.slip_start_s = s.start_s + s.move.CruiseMiddle() - 0.5 * slip.slip_deg / s.move.rate_dps;
        s.slip_end_s = s.slip_start_s + slip.slip_deg / s.move.rate_dps;
    }
    for (const Disturbance& d : o.faults.disturbances) {
        const DwellSpan& w = tl.dwells[static_cast<size_t>(d.dwell_index)];
        DisturbanceSpan s;
        s.dwell_index = d.dwell_index;
        s.sensor_id = d.sensor_id;
        s.offset_v = d.offset_v;
        s.start_s = w.start_s + d.start_after_s;
        s.end_s = d.duration_s > 0 ? s.start_s + d.duration_s : w.turns_start_s;
        tl.disturbances.push_back(s);
    }
}

struct UnitState {
    UnitTruth truth;
    ThermalPath path;
    RateNoise noise;
    std::mt19937_64 rng;
    double lpf1 = 0, lpf2 = 0;
};

class Adc {
public:
    explicit Adc(const AdcOptions& o) : o_(o), levels_(std::ldexp(1.0, o.bits)) {}
    // The volts the DAQ reports for a line at v read through `divider`.
    double Read(double v, double divider) const {
        if (o_.bits == 0) return v;
        const double code =
            std::clamp(std::floor(v * divider / o_.vref_v * levels_), 0.0, levels_ - 1);
        return (code + 0.5) * o_.vref_v / levels_ / divider;
    }

private:
    AdcOptions o_;
    double levels_;
};

}  // namespace

double Timeline::ReferenceAt(double t) const {
    double c = start_c;
    for (const Ramp& r : ramps) {
        if (t < r.t0_s) break;
        if (t >= r.t1_s) {
            c = r.to_c;
            continue;
        }
        return r.from_c + (r.to_c - r.from_c) * (t - r.t0_s) / (r.t1_s - r.t0_s);
    }
    return c;
}

double Timeline::TableAt(double t) const {
    double a = 0;
    for (const TurnSpan& s : turns) {
        if (t < s.start_s) break;
        a += s.move.AngleAt(t - s.start_s);
    }
    return a;
}

double Timeline::TableRateAt(double t) const {
    for (const TurnSpan& s : turns)
        if (t > s.start_s && t < s.end_s) return s.move.RateAt(t - s.start_s);
    return 0.0;
}

double Timeline::EncoderLossAt(double t) const {
    double loss = 0;
    for (const TurnSpan& s : turns) {
        if (s.slip_deg <= 0 || t <= s.slip_start_s) continue;
        const double moved = std::abs(s.move.AngleAt(std::min(t, s.end_s) - s.start_s) -
                                      s.move.AngleAt(s.slip_start_s - s.start_s));
        loss += (s.angle_deg < 0 ? -1.0 : 1.0) * std::min(s.slip_deg, moved);
    }
    return loss;
}

double Timeline::DisturbanceAt(const std::string& id, double t) const {
    double v = 0;
    for (const DisturbanceSpan& d : disturbances)
        if ((d.sensor_id.empty() || d.sensor_id == id) && t >= d.start_s && t < d.end_s)
            v += d.offset_v;
    return v;
}

Timeline BuildTimeline(const Options& o) {
    if (std::string p = o.Validate(); !p.empty()) throw std::invalid_argument(p);
    const ProfileOptions& p = o.profile;
    Timeline tl;
    tl.start_c = p.start_c;
    double t = p.lead_in_s, prev_c = p.start_c;
    for (size_t i = 0; i < p.steps.size(); ++i) {
        const Step& st = p.steps[i];
        DwellSpan d;
        d.index = static_cast<int>(i);
        d.setpoint_c = st.setpoint_c;
        d.ramp_start_s = t;
        const double ramp_s = std::abs(st.setpoint_c - prev_c) / p.ramp_c_per_min * 60.0;
        if (ramp_s > 0) tl.ramps.push_back({t, t + ramp_s, prev_c, st.setpoint_c});
        t += ramp_s;
        d.start_s = t;
        t += st.dwell_s;
        d.turns_start_s = t;
        if (st.turns) AddTurns(p, d.index, t, tl.turns);
        d.end_s = t;
        tl.dwells.push_back(d);
        prev_c = st.setpoint_c;
    }
    tl.duration_s = t + p.tail_s;
    ApplyFaults(o, tl);
    return tl;
}

Generated Generate(const Options& o, std::ostream& csv) {
    Generated g;
    g.timeline = BuildTimeline(o);
    g.units = DrawUnits(o);
    const Timeline& tl = g.timeline;
    const double dt = 1.0 / o.sample_rate_hz;
    const double alpha = 1.0 - std::exp(-2.0 * kPi * o.noise.lpf_hz * dt);
    const Adc adc(o.adc);
    // The noise (and the chamber's wander, the supply's, the encoder's phase) from noise_seed when
    // given: the same units with fresh noise, for a held-out record.
    const uint64_t noise_seed = o.noise_seed != 0 ? o.noise_seed : o.seed;
    Chamber chamber(o.thermal, o.profile.start_c, Stream(noise_seed, 1));
    std::vector<UnitState> units;
    for (size_t u = 0; u < g.units.size(); ++u) {
        UnitState s{g.units[u],
                    {},
                    RateNoise(o.noise, o.sample_rate_hz, Stream(noise_seed, 100 + u)),
                    std::mt19937_64(Stream(noise_seed, 200 + u))};
        s.path = ThermalPath{o.profile.start_c, o.profile.start_c, o.profile.start_c};
        s.lpf1 = s.lpf2 =
            s.truth.OffsetV(o.profile.start_c) + o.effects.warmup_v + o.effects.OutsideV(0.0);
        units.push_back(std::move(s));
    }
    std::mt19937_64 aux(Stream(noise_seed, 2));
    std::normal_distribution<double> normal(0.0, 1.0);
    const double res_deg = 360.0 / o.encoder_counts_per_rev;
    const double encoder_phase = std::uniform_real_distribution<double>(0.0, 1.0)(aux);
    double supply_wander = o.supply.wander_v * normal(aux);
    const double supply_phi = std::exp(-dt / o.supply.wander_tau_s);

    csv << "time_s,sensor_id,gyro_v,temp_v" << (o.supply.write ? ",supply_v" : "")
        << ",encoder_deg,chamber_c\n";
    const auto n = static_cast<int64_t>(std::floor(tl.duration_s * o.sample_rate_hz)) + 1;
    char row[256];
    for (int64_t k = 0; k < n; ++k) {
        const double t = static_cast<double>(k) * dt;
        const double air = k == 0 ? chamber.air_c() : chamber.Advance(dt, tl.ReferenceAt(t));
        supply_wander = supply_phi * supply_wander +
                        o.supply.wander_v * std::sqrt(1 - supply_phi * supply_phi) * normal(aux);
        const double supply = o.supply.nominal_v + supply_wander;
        const double supply_read =
            adc.Read(supply + o.supply.read_noise_v * normal(aux), o.adc.supply_divider);
        const double rate = tl.TableRateAt(t);
        const double enc = tl.TableAt(t) - tl.EncoderLossAt(t);
        const double encoder_deg = std::floor(enc / res_deg + encoder_phase) * res_deg;
        for (UnitState& s : units) {
            if (k > 0) s.path.Advance(o.thermal, s.truth.self_heating_c, air, dt);
            const double die = s.path.die_c;
            const double x =
                s.truth.OffsetV(die) + s.truth.SensitivityVPerDps(die) * (rate + s.noise.Next()) +
                o.effects.warmup_v * std::exp(-t / o.effects.warmup_tau_s) +
                o.effects.gradient_v_per_c * (s.path.board_c + s.truth.self_heating_c - die) +
                o.effects.supply_v_per_v * (supply - o.supply.nominal_v) + o.effects.OutsideV(t) +
                tl.DisturbanceAt(s.truth.sensor_id, t);
            s.lpf1 += alpha * (x - s.lpf1);
            s.lpf2 += alpha * (s.lpf1 - s.lpf2);
            const double gyro_v =
                adc.Read(std::clamp(s.lpf2, kRailLowV, kRailHighV), o.adc.divider);
            const double temp_v =
                adc.Read(s.truth.temp_v_at_25c + s.truth.temp_v_per_c * (s.path.line_c - 25.0) +
                             o.noise.temp_line_noise_v * normal(s.rng),
                         o.adc.divider);
            int len;
            if (o.supply.write)
                len = std::snprintf(row, sizeof row, "%.6f,%s,%.7f,%.7f,%.6f,%.4f,%.3f\n", t,
                                    s.truth.sensor_id.c_str(), gyro_v, temp_v, supply_read,
                                    encoder_deg, air);
            else
                len = std::snprintf(row, sizeof row, "%.6f,%s,%.7f,%.7f,%.4f,%.3f\n", t,
                                    s.truth.sensor_id.c_str(), gyro_v, temp_v, encoder_deg, air);
            csv.write(row, len);
            ++g.rows;
        }
    }
    return g;
}

Generated WriteRun(const Options& o, const std::string& csv_path, const std::string& truth_path) {
    std::ofstream csv(csv_path, std::ios::binary);
    if (!csv) throw std::runtime_error(csv_path + ": cannot be written");
    std::vector<char> buffer(1 << 20);
    csv.rdbuf()->pubsetbuf(buffer.data(), static_cast<std::streamsize>(buffer.size()));
    Generated g = Generate(o, csv);
    csv.flush();
    if (!csv) throw std::runtime_error(csv_path + ": write failed (disk full?)");
    std::ofstream truth(truth_path);
    if (!truth) throw std::runtime_error(truth_path + ": cannot be written");
    truth << TruthJson(o, g).dump(1) << "\n";
    if (!truth) throw std::runtime_error(truth_path + ": write failed (disk full?)");
    return g;
}

}  // namespace gyrocal::othersim
