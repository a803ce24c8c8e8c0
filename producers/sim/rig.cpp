#include "producers/sim/rig.hpp"

#include <algorithm>
#include <cmath>

namespace gyrocal::sim {

struct Rig::UnitState {
    UnitState(const RigConfig& c, int index)
        : rng(c.NoiseSeed(), UnitNoiseStream(index)), noise(c.noise, c.sample_rate_hz, rng) {}
    Rng rng;
    NoiseModel noise;
    double die_c = 0.0;
    double die_rate_c_per_s = 0.0;
    double sensor_c = 0.0;
    double hysteresis_mem_c = 0.0;  // play-operator memory
    double smooth_branch = 0.0;     // hysteresis_smooth's branch in (-1, 1), 0 at power-on
    double package_alpha = 0.0;     // cached for last_dt_s_
    double lpf_v = 0.0;
    bool lpf_primed = false;
    int64_t seq = 0;
};

namespace {

// ADC code of `v` (0 .. max_code, rounding to nearest) for a converter of `lsb_v` per code.
int32_t Code(double v, double lsb_v, int32_t max_code) {
    const double c = std::floor(v / lsb_v + 0.5);
    return static_cast<int32_t>(std::clamp(c, 0.0, static_cast<double>(max_code)));
}

// The smooth branch after a die travel of d_c (signed) from branch b: it relaxes toward the
// direction of travel exponentially in the travel, db/d|T| = (sign(dT) - b) / travel_c, so a
// reversal turns it over gradually instead of the play operator's straight ramp across a width.
double SmoothBranch(double b, double d_c, double travel_c) {
    if (d_c == 0.0) return b;
    const double target = d_c > 0.0 ? 1.0 : -1.0;
    return target + (b - target) * std::exp(-std::fabs(d_c) / travel_c);
}

// The sum of the offset effects [V] at one sample. Each is skipped when off so that "off" is
// bit-identical; the candidates' order of summation is the one the rig always had.
double EffectOffsetV(const RigConfig& c, const GyroTruth& t, double t_on_s) {
    const EffectsConfig& fx = c.effects;
    double v = 0.0;
    if (fx.temp_rate_v_per_c_per_min != 0.0)
        v += fx.temp_rate_v_per_c_per_min * t.die_rate_c_per_min;
    if (fx.hysteresis_v != 0.0) v += 0.5 * fx.hysteresis_v * t.hysteresis_branch;
    if (fx.temp_cubic_v_per_c3 != 0.0) {
        const double dt = t.die_c - kTruthT0C;
        v += fx.temp_cubic_v_per_c3 * dt * dt * dt;
    }
    if (fx.supply_v_per_v != 0.0) v += fx.supply_v_per_v * (t.supply_true_v - c.supply.nominal_v);
    if (fx.warmup_v != 0.0) v += fx.warmup_v * std::exp(-t_on_s / fx.warmup_tau_s);
    if (fx.aging_v_per_h != 0.0) v += fx.aging_v_per_h * t_on_s / 3600.0;
    if (fx.compressor_v != 0.0) {
        v += fx.compressor_v * std::sin(2.0 * M_PI * t_on_s / fx.compressor_period_s);
    }
    if (fx.gsens_v_per_g != 0.0) {
        v += fx.gsens_v_per_g * std::sin(fx.tilt_deg * M_PI / 180.0) *
             std::cos(t.table_angle_deg * M_PI / 180.0);
    }
    if (fx.hysteresis_smooth_v != 0.0)
        v += 0.5 * fx.hysteresis_smooth_v * t.hysteresis_smooth_branch;
    if (fx.warmup2_v != 0.0) v += fx.warmup2_v * std::exp(-t_on_s / fx.warmup2_tau_s);
    return v;
}

}  // namespace

Rig::Rig(const RigConfig& config)
    : config_((config.Validate(), config)),
      ids_(config.UnitIds()),
      chamber_(config.thermal, config.NoiseSeed()),
      table_(config.table),
      encoder_(config.encoder, Rng(config.NoiseSeed(), kStreamEncoder).Uniform()),
      supply_rng_(config.NoiseSeed(), kStreamSupply),
      now_utime_(config.start_utime),
      physics_utime_(config.start_utime) {
    for (size_t i = 0; i < ids_.size(); ++i) {
        units_.push_back(DrawUnit(config_, static_cast<int>(i), ids_[i]));
        auto s = std::make_unique<UnitState>(config_, static_cast<int>(i));
        s->die_c = config_.thermal.start_temp_c;
        s->sensor_c = s->die_c;
        s->hysteresis_mem_c = s->die_c;
        state_.push_back(std::move(s));
    }
    supply_drift_v_ = config_.supply.drift_std_v * supply_rng_.Normal();  // stationary start
    supply_true_v_ = config_.supply.nominal_v + supply_drift_v_;
    gyro_period_us_ = 1e6 / config_.sample_rate_hz;
    encoder_period_us_ = 1e6 / config_.encoder.rate_hz;
    chamber_period_us_ = 1e6 / config_.chamber_state_hz;
    if (config_.noise.lpf_hz > 0.0) {
        lpf_alpha_ = 1.0 - std::exp(-2.0 * M_PI * config_.noise.lpf_hz / config_.sample_rate_hz);
    }
    if (config_.adc.bits > 0) {
        max_code_ = static_cast<int32_t>((int64_t{1} << config_.adc.bits) - 1);
        lsb_v_ = config_.adc.vref_v / static_cast<double>(int64_t{1} << config_.adc.bits);
    }
}

Rig::~Rig() = default;

int64_t Rig::GridTime(double period_us, int64_t k) const {
    return config_.start_utime +
           static_cast<int64_t>(std::llround(period_us * static_cast<double>(k)));
}

int64_t Rig::next_event_utime() const {
    return std::min({GridTime(gyro_period_us_, gyro_k_), GridTime(encoder_period_us_, encoder_k_),
                     GridTime(chamber_period_us_, chamber_k_)});
}

CommandResult Rig::ChamberCommand(int64_t cmd_id, double setpoint_c, double ramp_c_per_min) {
    std::string why = chamber_.Command(cmd_id, setpoint_c, ramp_c_per_min);
    fault_ = why;
    return {why.empty(), why};
}

CommandResult Rig::TurntableCommand(int64_t cmd_id, double move_deg, double rate_dps,
                                    double accel_dps2) {
    const double now_s = (now_utime_ - config_.start_utime) * 1e-6;
    std::string why = table_.Command(cmd_id, move_deg, rate_dps, accel_dps2, now_s);
    fault_ = why;
    return {why.empty(), why};
}

void Rig::RunUntil(int64_t until_utime, RigSink& sink) {
    for (;;) {
        const int64_t t_chamber = GridTime(chamber_period_us_, chamber_k_);
        const int64_t t_encoder = GridTime(encoder_period_us_, encoder_k_);
        const int64_t t_gyro = GridTime(gyro_period_us_, gyro_k_);
        const int64_t t = std::min({t_chamber, t_encoder, t_gyro});
        if (t > until_utime) break;
        AdvancePhysics(t);
        now_utime_ = t;
        // Chamber first: a sink reacting to it (built-in profile) commands before the samples.
        if (t == t_chamber) {
            EmitChamber(t, sink);
            ++chamber_k_;
        }
        if (t == t_encoder) {
            EmitEncoder(t, sink);
            ++encoder_k_;
        }
        if (t == t_gyro) {
            EmitGyros(t, sink);
            ++gyro_k_;
        }
        if (stop_requested_) {
            stop_requested_ = false;
            break;
        }
    }
}

void Rig::AdvancePhysics(int64_t utime) {
    if (utime <= physics_utime_) return;
    const double dt_s = (utime - physics_utime_) * 1e-6;
    physics_utime_ = utime;
    if (dt_s != last_dt_s_) {
        last_dt_s_ = dt_s;
        supply_phi_ = std::exp(-dt_s / config_.supply.drift_tau_s);
        supply_drive_ = config_.supply.drift_std_v * std::sqrt(1.0 - supply_phi_ * supply_phi_);
        sensor_alpha_ = 1.0 - std::exp(-dt_s / config_.thermal.sensor_tau_s);
        for (size_t i = 0; i < state_.size(); ++i) {
            state_[i]->package_alpha = 1.0 - std::exp(-dt_s / units_[i].package_tau_s);
        }
    }
    chamber_.Advance(dt_s);
    const double air_c = chamber_.air_c();
    const double half_width = 0.5 * config_.effects.hysteresis_width_c;
    for (size_t i = 0; i < state_.size(); ++i) {
        UnitState& s = *state_[i];
        const double die_before_c = s.die_c;
        s.die_c += (air_c - s.die_c) * s.package_alpha;
        s.die_rate_c_per_s = (air_c - s.die_c) / units_[i].package_tau_s;
        s.sensor_c += (s.die_c - s.sensor_c) * sensor_alpha_;
        // Play operator: the memory follows the die only once it is half a width away.
        if (s.die_c > s.hysteresis_mem_c + half_width) s.hysteresis_mem_c = s.die_c - half_width;
        if (s.die_c < s.hysteresis_mem_c - half_width) s.hysteresis_mem_c = s.die_c + half_width;
        if (config_.effects.hysteresis_smooth_v != 0.0) {
            s.smooth_branch = SmoothBranch(s.smooth_branch, s.die_c - die_before_c,
                                           config_.effects.hysteresis_travel_c);
        }
    }
    supply_drift_v_ = supply_phi_ * supply_drift_v_ + supply_drive_ * supply_rng_.Normal();
    const double t_s = (utime - config_.start_utime) * 1e-6;
    supply_true_v_ =
        config_.supply.nominal_v + supply_drift_v_ +
        config_.supply.ripple_v * std::sin(2.0 * M_PI * config_.supply.ripple_hz * t_s);
    table_.AdvanceTo(t_s);
}

void Rig::EmitChamber(int64_t utime, RigSink& sink) {
    ChamberReading r;
    r.utime = utime;
    r.seq = chamber_seq_++;
    r.cmd_id = chamber_.cmd_id();
    r.setpoint_c = chamber_.setpoint_c();
    r.air_c = chamber_.air_c();
    r.at_setpoint = chamber_.at_setpoint();
    r.fault = fault_;
    sink.OnChamber(r);
}

void Rig::EmitEncoder(int64_t utime, RigSink& sink) {
    EncoderReading r;
    r.utime = utime;
    r.seq = encoder_seq_++;
    table_.At((utime - config_.start_utime) * 1e-6, r.true_angle_deg, r.true_rate_dps);
    r.counts = encoder_.Counts(r.true_angle_deg);
    r.counts_per_rev = encoder_.counts_per_rev();
    r.angle_deg = encoder_.AngleOf(r.counts);
    sink.OnEncoder(r);
}

Rig::SupplyScan Rig::ScanSupply() {
    const RigConfig& c = config_;
    // One supply for all units, measured once per scan.
    const double supply_meas_v = supply_true_v_ + c.supply.noise_v * supply_rng_.Normal();
    SupplyScan scan;
    scan.v = supply_meas_v;
    if (c.adc.bits > 0) {
        scan.counts = Code(supply_meas_v * c.adc.supply_divider, lsb_v_, max_code_);
        scan.v = scan.counts * lsb_v_ / c.adc.supply_divider;
    }
    return scan;
}

GyroTruth Rig::TruthOf(size_t i, double t_on_s, double table_angle_deg, double table_rate_dps,
                       double& temp_noise_v) {
    const RigConfig& c = config_;
    const EffectsConfig& fx = c.effects;
    UnitState& s = *state_[i];
    const UnitTruth& u = units_[i];
    GyroTruth truth;
    truth.air_c = chamber_.air_c();
    truth.die_c = s.die_c;
    truth.die_rate_c_per_min = s.die_rate_c_per_s * 60.0;
    truth.sensor_state_c = s.sensor_c;
    truth.rate_true_dps = table_rate_dps;
    truth.supply_true_v = supply_true_v_;
    truth.hysteresis_branch = (s.die_c - s.hysteresis_mem_c) / (0.5 * fx.hysteresis_width_c);
    truth.hysteresis_smooth_branch = s.smooth_branch;
    truth.table_angle_deg = table_angle_deg;
    // Always the same draws per sample, whatever is switched on.
    truth.rate_noise_dps = s.noise.Next(s.rng);
    temp_noise_v = c.noise.temp_noise_v * s.rng.Normal();

    truth.offset_v = u.OffsetV(s.die_c);
    truth.sensitivity_v_per_dps = u.SensitivityVPerDps(s.die_c);
    // Undeclared effects: each skipped entirely when 0 so that "off" is bit-identical.
    truth.effect_offset_v = EffectOffsetV(c, truth, t_on_s);
    if (fx.sf_asymmetry != 0.0 && table_rate_dps != 0.0) {
        truth.effect_sens_factor =
            table_rate_dps > 0.0 ? 1.0 + 0.5 * fx.sf_asymmetry : 1.0 - 0.5 * fx.sf_asymmetry;
    }
    return truth;
}

double Rig::FilteredOutputV(size_t i, const GyroTruth& truth) {
    const GyroPreset& p = config_.preset;
    UnitState& s = *state_[i];
    const double rate_dps =
        std::clamp(truth.rate_true_dps + truth.rate_noise_dps, -p.range_dps, p.range_dps);
    double sens = truth.sensitivity_v_per_dps;
    if (truth.effect_sens_factor != 1.0) sens *= truth.effect_sens_factor;
    double offset = truth.offset_v;
    if (truth.effect_offset_v != 0.0) offset += truth.effect_offset_v;
    const double v = std::clamp(offset + sens * rate_dps, p.rail_low_v, p.rail_high_v);
    if (!s.lpf_primed) {  // powered up settled: no filter transient at t = 0
        s.lpf_v = v;
        s.lpf_primed = true;
    } else {
        s.lpf_v += (v - s.lpf_v) * lpf_alpha_;
    }
    return s.lpf_v;
}

GyroReading Rig::ReadUnit(int64_t utime, size_t i, double gyro_analog_v, double temp_noise_v,
                          const SupplyScan& supply) {
    const GyroPreset& p = config_.preset;
    const double sensor_read_c = state_[i]->sensor_c + units_[i].temp_sensor_offset_c;
    const double temp_analog_v = p.temp_transfer.TempV(sensor_read_c) + temp_noise_v;

    GyroReading r;
    r.utime = utime;
    r.unit_index = static_cast<int>(i);
    r.sensor_id = &ids_[i];
    r.seq = state_[i]->seq++;
    r.has_adc = config_.adc.bits > 0;
    r.supply_v = supply.v;
    if (r.has_adc) {
        r.gyro_counts = Code(gyro_analog_v, lsb_v_, max_code_);
        r.temp_counts = Code(temp_analog_v, lsb_v_, max_code_);
        r.supply_counts = supply.counts;
        r.gyro_v = r.gyro_counts * lsb_v_;
        r.temp_v = r.temp_counts * lsb_v_;
    } else {
        r.gyro_v = gyro_analog_v;
        r.temp_v = temp_analog_v;
    }
    r.temp_c = p.temp_transfer.TempC(r.temp_v);
    return r;
}

void Rig::EmitGyros(int64_t utime, RigSink& sink) {
    const double t_on_s = (utime - config_.start_utime) * 1e-6;
    double table_angle_deg = 0.0, table_rate_dps = 0.0;
    table_.At(t_on_s, table_angle_deg, table_rate_dps);
    const SupplyScan supply = ScanSupply();
    for (size_t i = 0; i < state_.size(); ++i) {
        double temp_noise_v = 0.0;
        const GyroTruth truth = TruthOf(i, t_on_s, table_angle_deg, table_rate_dps, temp_noise_v);
        const double gyro_analog_v = FilteredOutputV(i, truth);
        sink.OnGyro(ReadUnit(utime, i, gyro_analog_v, temp_noise_v, supply), truth);
    }
}

}  // namespace gyrocal::sim
