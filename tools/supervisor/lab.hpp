#pragma once
// How `gyrocal calibrate` lays the process graph over a lab's hosts, and what it does when one of
// its processes dies. Pure: names and rules, no processes, no bus, no clock.
//
// Roles: one `gyrocal calibrate --role R` per host, every host on the same LCM group:
//   producers   the source: the simulated rig and the sequencer (or measured data and the run's
//               start/stop); it starts publishing only once it hears every consumer's heartbeat
//   processors  plateau detector, rotation estimator, fitter, compensator
//   recorder    the recorder (on the database's host) and the watch (progress, coefficient table)
//   all         all of it on this host (the default)
//
// Crash policy: a child that ends while its run goes on. Why each:
//   gyrocal-recorder     restart: it continues the open run of its bus and resumes seq tracking
//                        from the database, so what it missed while down is counted as gaps
//   gyrocal-plateau,     restart: they learn the run from the "restart" run event; a window or a
//   gyrocal-rotation     turn cut short is refused, and the sequencer orders the turn again
//   gyrocal-fitter       restart, then its points come back from the database (the role holding
//                        the database publishes the run's stored plateaus and rotations again)
//   gyrocal-compensator  restart, then the newest coefficient set of each sensor likewise
//   gyrocal-sequencer    restart, resuming its run at the setpoint it was at (known from the bus)
//   the source (rig,     abort the run: the simulated chamber and units, or the position in the
//   csv, lines, log)     data, die with it; a restart would publish a different experiment
// A process that dies more than max_restarts times in one run aborts the run.
#include <map>
#include <optional>
#include <string>
#include <string_view>

namespace gyrocal::supervisor {

enum class Role { kAll, kProducers, kProcessors, kRecorder };
std::optional<Role> ParseRole(std::string_view text);
const char* RoleName(Role role);
// True when a host of `role` runs `process` (an executable's file name).
bool RoleRuns(Role role, std::string_view process);

enum class OnCrash { kRestart, kAbortRun };
// What to do when `process` ends unexpectedly during a run (see above); unknown names abort.
OnCrash CrashPolicy(std::string_view process);

// What a restarted process needs given back, and who gives it.
enum class Recovery {
    kNone,            // it rebuilds its state from the live bus
    kStoredPoints,    // the run's plateaus and sensitivity points, from the database
    kStoredCoeffs,    // the newest coefficient set of each sensor, from the database
    kResumeSequence,  // the sequencer's run id, sensors and setpoint, from the bus
};
Recovery RecoveryOf(std::string_view process);

// Restarts per process name within one run.
class RestartBudget {
public:
    explicit RestartBudget(int max_restarts) : max_(max_restarts) {}
    // Counts one restart of `process`; false when it would exceed the budget.
    bool Take(const std::string& process);
    int used(const std::string& process) const;
    int max() const { return max_; }

private:
    int max_;
    std::map<std::string, int> used_;
};

// The LCM URL of chamber `chamber` (1-based): the same group, port + chamber - 1, options kept.
// Chamber 1 is `url` itself. Throws std::invalid_argument naming --chamber and what is valid.
std::string ChamberUrl(const std::string& url, int chamber);

}  // namespace gyrocal::supervisor
