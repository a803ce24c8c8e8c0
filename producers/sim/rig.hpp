#pragma once
// The simulated rig: one chamber, one turntable with its encoder, and N gyro units on the table
// in the chamber, on a simulated clock (utime, microseconds). No LCM, no wall clock: the caller
// says up to which simulated time to run, and readings come out through a RigSink in time order.
//
// Events: every gyro sample time (all units sampled together, one ADC scan), every encoder time,
// every CHAMBER_STATE time, on their own grids start_utime + round(k * period). Before each
// event the physics advances from the previous event time:
//   chamber air (ramp-limited reference + settling lag + fluctuation)
//   -> each unit's die temperature (first-order, its package tau)
//   -> each unit's temperature-sensor state (first-order, sensor tau)
//   supply drift (OU); turntable angle and rate are exact functions of time.
// A gyro sample of unit u at time t:
//   rate   = clamp(table_rate + noise_u, +-range)             [deg/s]
//   v      = offset_u(T_die) + effects + S_u(T_die) * asym * rate, clamped to the output rails
//            (effects: EffectsConfig; each one's formula in producers/sim/README.md)
//   gyro_v = ADC(LPF(v)),  temp_v = ADC(V25 + k_T (sensor_state + sensor_offset_u - 25) + noise)
//   temp_c = 25 + (temp_v - V25) / k_T  (the preset's sensor::TempTransfer, as the CSV sources)
// Commands take effect at now_utime() (the last processed event). A sink may issue commands from
// its callbacks (the built-in profile does so from OnChamber).
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "producers/sim/chamber.hpp"
#include "producers/sim/config.hpp"
#include "producers/sim/noise.hpp"
#include "producers/sim/rng.hpp"
#include "producers/sim/turntable.hpp"
#include "producers/sim/unit_model.hpp"

namespace gyrocal::sim {

struct GyroReading {  // what a DAQ would read: becomes gyro_sample_t
    int64_t utime = 0;
    int unit_index = 0;
    const std::string* sensor_id = nullptr;  // owned by the Rig: valid while it lives
    int64_t seq = 0;
    double gyro_v = 0.0;
    double temp_v = 0.0;
    double temp_c = 0.0;
    double supply_v = 0.0;
    bool has_adc = false;
    int32_t gyro_counts = 0;
    int32_t temp_counts = 0;
    int32_t supply_counts = 0;
};

struct GyroTruth {  // never published: for tests and evaluations
    double air_c = 0.0;
    double die_c = 0.0;
    double die_rate_c_per_min = 0.0;
    double sensor_state_c = 0.0;  // lagged die temperature, before the sensor's offset
    double rate_true_dps = 0.0;
    double rate_noise_dps = 0.0;
    double offset_v = 0.0;               // truth curve at die_c (effects excluded)
    double sensitivity_v_per_dps = 0.0;  // truth curve at die_c (effects excluded)
    double effect_offset_v = 0.0;        // sum of the effects' offset terms
    double effect_sens_factor = 1.0;     // scale-factor asymmetry factor
    double supply_true_v = 0.0;
    double hysteresis_branch = 0.0;  // [-1, 1]: -1 cooling branch, +1 heating branch
    // [-1, 1]: the smooth branch (hysteresis_smooth), 0 at power-on; only tracked when that
    // effect is on (0 otherwise).
    double hysteresis_smooth_branch = 0.0;
    double table_angle_deg = 0.0;  // [deg] the table's true angle since power-on
};

struct EncoderReading {
    int64_t utime = 0;
    int64_t seq = 0;
    int64_t counts = 0;
    int32_t counts_per_rev = 0;
    double angle_deg = 0.0;       // counts * 360 / cpr
    double true_angle_deg = 0.0;  // not published
    double true_rate_dps = 0.0;   // not published
};

struct ChamberReading {
    int64_t utime = 0;
    int64_t seq = 0;
    int64_t cmd_id = -1;
    double setpoint_c = 0.0;
    double air_c = 0.0;
    bool at_setpoint = false;
    std::string fault;
};

class RigSink {
public:
    virtual ~RigSink() = default;
    virtual void OnGyro(const GyroReading&, const GyroTruth&) {}
    virtual void OnEncoder(const EncoderReading&) {}
    virtual void OnChamber(const ChamberReading&) {}
};

struct CommandResult {
    bool accepted = false;
    std::string reason;  // why it was refused; "" when accepted
};

class Rig {
public:
    // Throws ConfigError when the configuration is not valid.
    explicit Rig(const RigConfig& config);
    ~Rig();

    const RigConfig& config() const { return config_; }
    const std::vector<UnitTruth>& units() const { return units_; }
    const std::vector<std::string>& sensor_ids() const { return ids_; }
    int64_t now_utime() const { return now_utime_; }
    int64_t next_event_utime() const;
    double sim_seconds() const { return (now_utime_ - config_.start_utime) * 1e-6; }

    // Processes every event with utime <= until_utime, in time order; returns early after the
    // event time at which a sink called StopAfterCurrentEvent().
    void RunUntil(int64_t until_utime, RigSink& sink);
    // From a sink callback: finish the current event time, then return from RunUntil (so a run
    // that ends on a simulated-time condition ends at the same sample whatever the batching).
    void StopAfterCurrentEvent() { stop_requested_ = true; }

    // Orders; a refusal leaves the rig unchanged and sets the fault that CHAMBER_STATE reports.
    // An accepted order clears it.
    CommandResult ChamberCommand(int64_t cmd_id, double setpoint_c, double ramp_c_per_min);
    CommandResult TurntableCommand(int64_t cmd_id, double move_deg, double rate_dps,
                                   double accel_dps2);

    const ChamberModel& chamber() const { return chamber_; }
    bool table_busy() const { return table_.busy(); }
    const std::string& fault() const { return fault_; }

private:
    struct UnitState;
    void AdvancePhysics(int64_t utime);
    // The supply as every unit's scan reads it: [V] (through the ADC when there is one) and
    // its ADC code (0 without an ADC).
    struct SupplyScan {
        double v = 0.0;
        int32_t counts = 0;
    };
    SupplyScan ScanSupply();
    // Unit i's truth at t_on_s [s] since power-on; draws the unit's noise, the same draws
    // whatever is switched on: the rate noise into the truth, the temperature line's into
    // `temp_noise_v` [V].
    GyroTruth TruthOf(size_t i, double t_on_s, double table_angle_deg, double table_rate_dps,
                      double& temp_noise_v);
    // Unit i's module output [V] for `truth`, clamped to the rails, through its low-pass filter.
    double FilteredOutputV(size_t i, const GyroTruth& truth);
    // What the DAQ reads of unit i (next seq), through the ADC when there is one.
    GyroReading ReadUnit(int64_t utime, size_t i, double gyro_analog_v, double temp_noise_v,
                         const SupplyScan& supply);
    void EmitGyros(int64_t utime, RigSink& sink);
    void EmitEncoder(int64_t utime, RigSink& sink);
    void EmitChamber(int64_t utime, RigSink& sink);
    int64_t GridTime(double period_us, int64_t k) const;

    RigConfig config_;
    std::vector<std::string> ids_;
    std::vector<UnitTruth> units_;
    std::vector<std::unique_ptr<UnitState>> state_;
    ChamberModel chamber_;
    TurntableModel table_;
    EncoderModel encoder_;
    Rng supply_rng_;
    double supply_drift_v_ = 0.0;
    double supply_true_v_ = 0.0;
    std::string fault_;
    bool stop_requested_ = false;

    int64_t now_utime_;
    int64_t physics_utime_;
    double gyro_period_us_, encoder_period_us_, chamber_period_us_;
    int64_t gyro_k_ = 0, encoder_k_ = 0, chamber_k_ = 0;  // index of the next event of each grid
    int64_t encoder_seq_ = 0, chamber_seq_ = 0;

    // Cached per-step factors (the step is nearly always one sample period).
    double last_dt_s_ = -1.0;
    double supply_phi_ = 0.0, supply_drive_ = 0.0, sensor_alpha_ = 0.0;
    double lpf_alpha_ = 1.0;
    double lsb_v_ = 0.0;
    int32_t max_code_ = 0;
};

}  // namespace gyrocal::sim
