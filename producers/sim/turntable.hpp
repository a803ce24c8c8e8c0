#pragma once
// The turntable: relative moves with a trapezoidal rate profile (accelerate at a, cruise at v,
// decelerate at a; a triangle when the move is too short to reach v). Orders queue and run one
// after the other. Position and rate are exact functions of time, so they do not depend on how
// often anyone looks. The optical encoder quantizes the angle: counts = floor(angle * cpr / 360 +
// phase), phase being where the disk's first edge happened to sit at power-on (seeded).
#include <cstdint>
#include <deque>
#include <string>

#include "producers/sim/config.hpp"

namespace gyrocal::sim {

struct TableMove {
    int64_t cmd_id = 0;
    double distance_deg = 0.0;  // signed
    double rate_dps = 0.0;      // cruise magnitude
    double accel_dps2 = 0.0;    // magnitude
    double start_s = 0.0;       // [s] sim time the move began (set when it starts)
    double Duration() const;
    // Position [deg] and rate [deg/s] at `elapsed_s` after the start (clamped to the move).
    void At(double elapsed_s, double& pos_deg, double& rate_dps) const;
};

class TurntableModel {
public:
    explicit TurntableModel(const TableConfig& config) : config_(config) {}

    // Queues a move to start at time now_s (or after the queued ones); "" when accepted, else why
    // it was refused (nothing queued).
    std::string Command(int64_t cmd_id, double move_deg, double rate_dps, double accel_dps2,
                        double now_s);
    // Brings the queue up to time t_s (finished moves fold into the base angle). t_s never
    // decreases between calls.
    void AdvanceTo(double t_s);
    // Angle [deg, cumulative since power-on] and rate [deg/s] at t_s (after AdvanceTo(t_s)).
    void At(double t_s, double& angle_deg, double& rate_dps) const;
    bool busy() const { return !queue_.empty(); }

    static constexpr size_t kMaxQueuedMoves = 16;

private:
    TableConfig config_;
    std::deque<TableMove> queue_;
    double base_angle_deg_ = 0.0;
};

class EncoderModel {
public:
    EncoderModel(const EncoderConfig& config, double phase_counts)
        : counts_per_rev_(config.lines_per_rev * config.quadrature), phase_(phase_counts) {}
    int32_t counts_per_rev() const { return counts_per_rev_; }
    int64_t Counts(double angle_deg) const;
    double AngleOf(int64_t counts) const { return counts * 360.0 / counts_per_rev_; }

private:
    int32_t counts_per_rev_;
    double phase_;  // [count] in [0, 1)
};

}  // namespace gyrocal::sim
