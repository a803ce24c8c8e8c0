#pragma once
// The launcher behind `gyrocal calibrate` (calibrate.hpp says what it does): the run and its watch
// in calibrate.cpp, the children and their supervision in supervision.cpp.
#include <chrono>
#include <deque>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "gyrocal/analysis_t.hpp"
#include "gyrocal/coeff_set_t.hpp"
#include "gyrocal/fit_report_t.hpp"
#include "gyrocal/run_event_t.hpp"
#include "lcmtypes/bus/bus.hpp"
#include "lcmtypes/flow/flow_acker.hpp"
#include "lcmtypes/launch/child_process.hpp"
#include "tools/supervisor/final_verdict.hpp"
#include "tools/supervisor/lab.hpp"
#include "tools/supervisor/progress.hpp"
#include "tools/supervisor/supervisor.hpp"

namespace gyrocal::supervisor {

using Clock = std::chrono::steady_clock;

class Calibration {
public:
    Calibration(CalibrateOptions o, StoreServices services);
    int Run();

private:
    struct Child {
        std::string name;               // executable file name
        std::vector<std::string> argv;  // as first started
        std::string log;
        std::unique_ptr<launch::ChildProcess> proc;
        int instance = 0;                         // restarts so far
        std::vector<std::string> previous_cause;  // error lines of the instance last restarted
    };
    struct PendingRecovery {
        Clock::time_point due;
        Recovery what;
        std::string run_id;
        std::string process;
    };

    // calibrate.cpp: the run.
    void Subscribe();
    void OnRunEvent(const run_event_t& e);
    bool StartConsumers();
    bool StartProducers();
    void StartSim();
    std::vector<std::string> SimPace() const;
    void StartMeasured();
    int Watch();
    bool DetectEnd();  // true once the run has ended (this role's view)
    bool WaitsForCoeffs() const;
    std::string ConfigJson() const;
    bool IsRamp() const;  // --profile names a continuous (ramp) profile
    void AnnounceRun(const std::string& event, const std::string& reason);
    void ShowProgress(bool force);
    std::set<std::string> Sensors() const;
    bool HaveFinalCoeffs() const;
    bool ClosedLoop() const;  // the fitter makes each unit's final set on every still sample
    std::string ClosedLoopLines() const;  // per unit: outcome, error before/after (closed_loop.cpp)
    FinalVerdict Verdict() const;  // per unit: complete, partial or none, from the final reports
    int Finish(int code);

    // supervision.cpp: the children.
    bool Runs(const std::string& process) const { return RoleRuns(role_, process); }
    Child& Start(const std::string& exe, std::vector<std::string> args);
    bool AwaitHeartbeats(const std::set<std::string>& names, std::chrono::seconds limit,
                         const std::string& hint);
    bool AwaitPid(const Child& c, std::chrono::seconds limit);
    // Handles children that ended; an exit code when this launcher must end now.
    std::optional<int> Supervise();
    std::optional<int> HandleCrash(Child& c, const launch::ExitStatus& how);
    bool Restart(Child& c, const launch::ExitStatus& how);
    std::vector<std::string> ResumeArgs(const Child& c) const;
    void PublishRestart(const Child& c, const launch::ExitStatus& how, int previous_pid);
    int AbortRun(const std::string& reason);
    // The child's own error lines from its log (child_errors.hpp), the cause shown under the
    // abort line and stored with the run.
    std::vector<std::string> CauseOf(const Child& c) const;
    void OnRestartEvent(const run_event_t& e);
    void RecoverDue();
    void StopAll();
    bool RunIsOn() const { return !run_id_.empty() && !run_ended_; }

    CalibrateOptions o_;
    StoreServices services_;  // what needs the store (supervisor.hpp)
    Source source_kind_;
    Role role_;
    bus::Bus bus_;
    // This launcher receives everything on the bus too (coefficient sets, fit reports): it
    // answers the sources' flow marks like every process, so they pace on it as well.
    flow::FlowAcker acker_;
    std::string url_;
    std::deque<Child> children_;  // deque: Start() hands out references that must stay valid
    Child* sequencer_ = nullptr;
    Child* source_ = nullptr;
    RestartBudget budget_;
    std::map<std::string, std::set<int>> heard_;  // process name -> pids heard in STATUS
    std::unique_ptr<Progress> progress_;
    std::vector<std::string> run_sensors_;
    std::set<std::string> stability_sensors_;
    std::map<std::string, coeff_set_t> coeffs_;          // newest per sensor
    std::set<std::string> final_coeffs_;                 // sensors with a set after the stop
    std::map<std::string, fit_report_t> final_reports_;  // the fitter's verdict at the stop
    // The closed loop (plateau runs): each unit's final report and analysis of source
    // closed-loop, and the newest plateau set (source fitter) beside it.
    std::map<std::string, fit_report_t> loop_reports_;
    std::map<std::string, analysis_t> loop_analyses_;
    std::map<std::string, coeff_set_t> plateau_sets_;
    std::vector<PendingRecovery> recoveries_;
    bool stop_seen_ = false;
    bool run_ended_ = false;
    std::string run_id_;
    std::string run_outcome_;
    std::string input_sha256_;  // of --input, recorded with the run
    int setpoint_index_ =
        -1;  // of the latest "setpoint" event (a restarted sequencer resumes there)
    double setpoint_c_ = 0;
    std::optional<Clock::time_point> ended_at_;
    Clock::time_point start_ = Clock::now();
    Clock::time_point last_line_{};
};

double SecondsSince(Clock::time_point t0);
std::string TailOf(const std::string& path, int lines);

}  // namespace gyrocal::supervisor
