#pragma once
// The continuous ramp procedure: the chamber never waits for a stable temperature.
//
//   start -> for each waypoint i of the profile (in order):
//              order the chamber to waypoint i at ramp_rate_c_per_min  (RUN_EVENT setpoint)
//              the leg ends dwell_s after the air came within reach_band_c of the waypoint
//              (the units' dies lag the air by the package time constant, so the ends of the
//              range are only measured after a dwell of a few of those)
//         -> stop ("completed")
//   meanwhile, every turn_interval_s of data time from the start: one +90/-90 pair (moves_deg),
//   each move awaited from every sensor (or rotation_timeout_s) as in the plateau procedure, but
//   never ordered again: the next pair comes soon enough, and a missing point is only noted.
//   The chamber keeps ramping during the turns: the rotation estimator removes a linear offset
//   drift across each turn (rotation_estimator.hpp), which is what a ramp gives.
//
// Starting from the room temperature, the default waypoints (-40, 85) give a cooling ramp to -40
// and a heating ramp through the whole range, so the temperature-rate and branch terms separate
// from the temperature polynomial; more waypoints give more legs.
//
// Early stop (target_offset_dps / target_sensitivity_pct > 0): once the run has ramped in both
// directions (the second leg has started), a coefficient set of each unit (OnCoefficients) whose
// uncertainty over the WHOLE planned range is within every target given ends the run at the next
// moment no turn is under way. Uncertainty outside the range the data covered is the model's own
// extrapolation (coeff_uncertainty.hpp), so an early set of half the range does not pass. The stop
// reason says how much chamber time the rest of the plan would have taken (saved_s()).
#include <map>
#include <string>
#include <vector>

#include "processors/sequencer/procedure.hpp"

namespace gyrocal::sequencer {

class RampProcedure : public Runner {
public:
    // Validates; throws std::invalid_argument (also when the profile is not continuous).
    explicit RampProcedure(ProcedureOptions options);

    std::vector<Order> OnTime(int64_t utime) override;
    std::vector<Order> OnPlateau(const std::string&, int64_t utime, double) override {
        return OnTime(utime);  // plateaus do not drive a ramp
    }
    std::vector<Order> OnSensitivity(const std::string& sensor_id, int64_t utime,
                                     bool accepted = true,
                                     const std::string& reject_reason = "") override;
    std::vector<Order> OnChamber(int64_t utime, double air_c) override;
    std::vector<Order> OnCoefficients(const std::string& sensor_id, int64_t utime,
                                      const CoeffUncertainty& u) override;

    int setpoint_index() const override { return leg_; }

    int turns_done() const { return turns_done_; }  // completed +90/-90 pairs
    double saved_s() const { return saved_s_; }     // [s] of the plan left at an early stop
    // [s] data time the rest of the plan needs from now (the current leg from the last air
    // temperature seen, its dwell, the later legs and dwells at ramp_rate_c_per_min).
    double RemainingPlanS() const;

private:
    std::vector<Order> EnterLeg(int index, int64_t utime);
    std::vector<Order> EnterMove(int index, int64_t utime);
    std::vector<Order> MoveDone(int64_t utime);
    std::vector<Order> Finish(const std::string& event, const std::string& reason) override;
    bool TargetsMet() const;
    double Waypoint(int i) const { return options_.profile.setpoints_c[static_cast<size_t>(i)]; }

    ProcedureOptions options_;
    int leg_ = -1;
    int64_t start_utime_ = 0;
    int64_t leg_start_utime_ = 0;
    int64_t reached_utime_ = -1;  // [us] the air reached the current waypoint; -1 = not yet
    int move_index_ = -1;
    int64_t move_start_utime_ = 0;
    int64_t next_turn_utime_ = 0;
    int64_t now_utime_ = 0;
    double air_c_ = NAN;
    std::map<std::string, CoeffUncertainty> uncertainty_;
    std::string finishing_;  // the stop reason once the plan is done or the targets are met
    int turns_done_ = 0;
    double saved_s_ = 0.0;
};

}  // namespace gyrocal::sequencer
