#pragma once
// What `gyrocal calibrate` shows while a run goes on, computed from the bus traffic it sees.
// Pure: fed decoded messages and the wall time, it returns the status line; no I/O.
#include <cstdint>
#include <map>
#include <set>
#include <string>
#include <utility>

#include "gyrocal/chamber_state_t.hpp"
#include "gyrocal/coeff_set_t.hpp"
#include "gyrocal/plateau_state_t.hpp"
#include "gyrocal/run_event_t.hpp"
#include "gyrocal/sensitivity_point_t.hpp"
#include "gyrocal/status_t.hpp"

namespace gyrocal::supervisor {

class Progress {
public:
    explicit Progress(int setpoints_total, int moves_per_setpoint)
        : setpoints_total_(setpoints_total), moves_per_setpoint_(moves_per_setpoint) {}

    void OnRunEvent(const run_event_t& e);
    void OnChamber(const chamber_state_t& s);
    void OnStability(const plateau_state_t& s);
    void OnSensitivity(const sensitivity_point_t& s);
    void OnStatus(const status_t& s);
    void OnCoeffs(const coeff_set_t& c);

    // Fraction of the procedure done, 0..1 (setpoints weighted equally, moves inside them).
    double FractionDone() const;
    // Wall seconds left, extrapolated from the fraction done so far; <0 when unknown.
    double EtaS(double wall_elapsed_s) const;
    std::string Line(double wall_elapsed_s) const;

    const std::string& run_id() const { return run_id_; }
    const std::string& last_event() const { return last_event_; }
    int64_t drops() const;  // sequence gaps + decode errors + queue drops + handler errors, all
                            // processes
    int rotations_accepted() const { return rotations_accepted_; }
    int rotations_rejected() const { return rotations_rejected_; }

private:
    int setpoints_total_;
    int moves_per_setpoint_;
    int setpoint_index_ = -1;
    int moves_done_at_setpoint_ = 0;
    double setpoint_c_ = 0;
    bool have_chamber_ = false;
    double air_c_ = 0;
    int64_t first_utime_ = -1;
    int64_t last_utime_ = 0;
    std::string run_id_;
    std::string last_event_;
    std::map<std::string, plateau_state_t> stability_;
    std::map<std::string, int64_t> losses_by_process_;
    std::map<std::string, int> coeffs_by_sensor_;
    std::set<std::pair<std::string, int64_t>> points_seen_;  // (sensor_id, rotation_id)
    int rotations_accepted_ = 0;
    int rotations_rejected_ = 0;
};

}  // namespace gyrocal::supervisor
