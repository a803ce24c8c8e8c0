#pragma once
// The calibration procedure of the seed (METHOD.md) as a state machine with no I/O:
//
//   start -> for each setpoint i:
//              command chamber to setpoint i            (RUN_EVENT setpoint, CHAMBER_CMD)
//              wait for a plateau from every sensor     (PLATEAU_<id> newer than the command)
//              for each move in moves_deg (+90, -90):
//                  command the turntable               (RUN_EVENT rotation, TURNTABLE_CMD)
//                  wait for a sensitivity point from every sensor (SENSITIVITY_<id>)
//         -> stop ("completed")
//
// Time is data time only (utime of the messages fed in), so the procedure runs as fast as the
// simulated rig or a replayed log, and a missing plateau is decided on data time: a setpoint
// whose plateaus do not all arrive within plateau_timeout_s ends the run with outcome "abort"
// and a reason naming the sensors that never settled (a chamber fault), never a hang. A move
// whose sensitivity points do not all arrive within rotation_timeout_s, or arrive rejected (a
// turn with samples lost on the network, a slip), is ordered again after retry_wait_s of data
// (the estimator needs a rest window before the turn, and the first samples after a network
// hole are no rest window), up to move_attempts in all;
// a move still missing after that is noted, named in the stop event's reason, and skipped: the
// offset calibration of that setpoint stays valid without it.
//
// Resume (a sequencer restarted after a crash, resume_setpoint_index >= 0): no "start"; the run
// goes on at that setpoint, which is taken again from its chamber order (its plateaus and moves:
// what the dead sequencer was waiting for is not known, so nothing of that setpoint is assumed).
#include <cmath>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <variant>
#include <vector>

namespace gyrocal::sequencer {

struct Profile {
    std::string name;
    std::vector<double> setpoints_c;  // continuous: the waypoints the ramp turns at, in order
    bool continuous = false;  // ramp through the waypoints without waiting (ramp_procedure.hpp)
};

// Named profiles.
// "six" (default): 25, -40, -10, 45, 65, 85 °C. Six temperatures let each unit's order be chosen
//   on evidence: its cubic reference keeps 2 dof (five points leave it 1), so a real cubic is
//   found per unit. Chamber time stays that of "five": the first setpoint is the room temperature
//   the units start at (no ramp, only the settling check), the ramp total is the same
//   (25 -> -40 -> 85 °C), and there are five settled setpoints after it as in "five" (measured
//   chamber time and order choices: docs/procedures.md#why-profile-six).
// "five": -40, -10, 25, 55, 85 °C, the previous default, unchanged.
// "seed3": the seed note's -10/30/60 °C.
// "ramp": continuous ramps from the start temperature to -40 °C (cooling) and on to 85 °C
//   (heating), turning the table at intervals on the move (ramp_procedure.hpp).
std::optional<Profile> NamedProfile(const std::string& name);
std::vector<std::string> ProfileNames();
inline constexpr const char* kDefaultProfile = "six";
// "six (25,-40,-10,45,65,85 C), five (...), seed3 (...)": for help texts.
std::string ProfilesHelp();

struct ProcedureOptions {
    Profile profile;
    std::vector<std::string> sensor_ids;    // units whose plateaus/rotations are awaited
    double ramp_rate_c_per_min = 3.0;       // [degC/min] ordered chamber ramp rate
    double plateau_timeout_s = 3.0 * 3600;  // [s] data time per setpoint before "chamber fault"
    std::vector<double> moves_deg = {90.0, -90.0};  // [deg] turntable moves at each setpoint
    double rotation_rate_dps = 30.0;                // [deg/s] cruise rate of each move
    double rotation_accel_dps2 = 60.0;              // [deg/s^2]
    double rotation_timeout_s = 120.0;              // [s] data time per move
    int move_attempts = 2;           // [count] orders of one move before it is given up, 1..5
    double retry_wait_s = 10.0;      // [s] data time at rest before a move is ordered again
    int resume_setpoint_index = -1;  // >= 0: resume a run there (no start event); -1 = new run
    // Continuous profiles only (ramp_procedure.hpp):
    double turn_interval_s = 300.0;       // [s] data time from one +90/-90 pair to the next
    double dwell_s = 300.0;               // [s] held at a waypoint once the air is there
    double reach_band_c = 1.0;            // [degC] air this close to a waypoint has reached it
    double target_offset_dps = 0.0;       // [deg/s] early stop when every unit's offset is this
                                          // well known over the range; 0 = not a criterion
    double target_sensitivity_pct = 0.0;  // [%] same for the sensitivity; 0 = not a criterion
    // Throws std::invalid_argument naming the field and its valid range.
    void Validate() const;
};

// What the procedure wants published. The shell turns these into LCM messages.
struct ChamberOrder {
    double setpoint_c;
    double ramp_rate_c_per_min;
};
struct TurntableOrder {
    double move_deg;
    double rate_dps;
    double accel_dps2;
};
struct RunEventOrder {
    std::string event;  // start, setpoint, rotation, stop, abort
    std::string reason;
    int setpoint_index;  // -1 when not applicable
    double setpoint_c;   // NaN when not applicable
};
using Order = std::variant<ChamberOrder, TurntableOrder, RunEventOrder>;

enum class Phase { kIdle, kWaitPlateau, kWaitRotation, kWaitRetry, kRamping, kDone };
const char* PhaseName(Phase p);

// How well one unit's newest coefficient set is known over the procedure's range (1 sigma, the
// worst temperature): what the early stop of a ramp run compares with its targets.
struct CoeffUncertainty {
    double offset_dps = NAN;       // [deg/s] offset uncertainty / sensitivity
    double sensitivity_pct = NAN;  // [%] sensitivity uncertainty / sensitivity
};

// What the sequencer process and the virtual lab drive: the plateau Procedure below or the
// continuous RampProcedure (ramp_procedure.hpp). MakeRunner picks by profile.continuous.
class Runner {
public:
    virtual ~Runner() = default;
    virtual std::vector<Order> OnTime(int64_t utime) = 0;
    virtual std::vector<Order> OnPlateau(const std::string& sensor_id, int64_t utime,
                                         double setpoint_c) = 0;
    virtual std::vector<Order> OnSensitivity(const std::string& sensor_id, int64_t utime,
                                             bool accepted = true,
                                             const std::string& reject_reason = "") = 0;
    // The chamber's air temperature (CHAMBER_STATE); the plateau procedure does not need it.
    virtual std::vector<Order> OnChamber(int64_t utime, double /*air_c*/) { return OnTime(utime); }
    // A unit's newest coefficient set, as its uncertainty; only a ramp run can stop on it.
    virtual std::vector<Order> OnCoefficients(const std::string&, int64_t utime,
                                              const CoeffUncertainty&) {
        return OnTime(utime);
    }
    // Operator stop (Ctrl-C): ends the run as "abort" with the reason given.
    std::vector<Order> Abort(const std::string& reason);
    // The run was ended by someone else (a supervisor's abort of this run): done, nothing ordered.
    void EndedElsewhere(const std::string& event, const std::string& reason);

    Phase phase() const { return phase_; }
    bool done() const { return phase_ == Phase::kDone; }
    virtual int setpoint_index() const = 0;
    const std::string& outcome() const { return outcome_; }  // "completed" or "abort"
    const std::string& outcome_reason() const { return outcome_reason_; }
    const std::vector<std::string>& notes() const { return notes_; }  // e.g. skipped moves
    std::set<std::string> pending_sensors() const { return pending_; }

protected:
    // Ends the run with a RUN_EVENT `event` ("stop" or "abort") and sets the outcome.
    virtual std::vector<Order> Finish(const std::string& event, const std::string& reason) = 0;

    // The state both procedures keep the same way: where the run is, whom it waits for, how it
    // ended.
    Phase phase_ = Phase::kIdle;
    std::set<std::string> pending_;
    std::string outcome_;
    std::string outcome_reason_;
    std::vector<std::string> notes_;
};

// Validates (throws std::invalid_argument naming the field).
std::unique_ptr<Runner> MakeRunner(ProcedureOptions options);

class Procedure : public Runner {
public:
    explicit Procedure(ProcedureOptions options);  // validates; throws std::invalid_argument

    // Data time advanced (any message). Starts the run on the first call; checks timeouts.
    std::vector<Order> OnTime(int64_t utime) override;
    // setpoint_c: the plateau's own setpoint (NaN when unknown); a plateau of another setpoint
    // (one that finished averaging just after the chamber was reordered) does not count.
    std::vector<Order> OnPlateau(const std::string& sensor_id, int64_t utime,
                                 double setpoint_c) override;
    // accepted false (reject_reason says why) asks for the move again (see move_attempts).
    std::vector<Order> OnSensitivity(const std::string& sensor_id, int64_t utime,
                                     bool accepted = true,
                                     const std::string& reject_reason = "") override;

    int setpoint_index() const override { return setpoint_index_; }
    int move_index() const { return move_index_; }

private:
    std::vector<Order> EnterSetpoint(int index, int64_t utime);
    std::vector<Order> EnterMove(int index, int64_t utime, const std::string& why = "");
    std::vector<Order> MoveDone(int64_t utime);  // every sensor answered or the move timed out
    std::vector<Order> Advance(int64_t utime);   // after a setpoint's plateaus or a move completes
    std::vector<Order> Finish(const std::string& event, const std::string& reason) override;

    ProcedureOptions options_;
    int setpoint_index_ = -1;
    int move_index_ = -1;
    int64_t phase_start_utime_ = 0;
    int64_t now_utime_ = 0;
    int move_attempt_ = 0;                            // 1-based attempt of the current move
    std::map<std::string, std::string> move_failed_;  // sensor -> why, for the current attempt
    std::string retry_why_;                           // kWaitRetry: what the next order says
};

}  // namespace gyrocal::sequencer
