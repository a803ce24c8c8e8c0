// The children of `gyrocal calibrate` and what happens when one dies (lab.hpp's crash policy).
#include <unistd.h>

#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>

#include "gyrocal/version.hpp"
#include "lcmtypes/channels/channels.hpp"
#include "lcmtypes/process/shutdown.hpp"
#include "lcmtypes/process/status.hpp"
#include "lcmtypes/text/join.hpp"
#include "tools/supervisor/child_errors.hpp"
#include "tools/supervisor/launcher.hpp"

namespace gyrocal::supervisor {
namespace {

using namespace std::chrono_literals;

// How long the database's host waits after a "restart" event before reading what to recover:
// the recorder commits every 200 ms (--batch-ms), so what was published before the restart
// is in the file by then.
constexpr auto kRecoveryDelay = 1s;

}  // namespace

Calibration::Child& Calibration::Start(const std::string& exe, std::vector<std::string> args) {
    Child c;
    c.name = std::filesystem::path(exe).filename().string();
    c.log = o_.log_dir + "/" + c.name + ".log";
    args.insert(args.begin(), {"--lcm-url", url_});
    args.insert(args.begin(), exe);
    c.argv = args;
    c.proc = std::make_unique<launch::ChildProcess>(args, c.log, c.log);
    children_.push_back(std::move(c));
    return children_.back();
}

bool Calibration::AwaitHeartbeats(const std::set<std::string>& names, std::chrono::seconds limit,
                                  const std::string& hint) {
    const auto deadline = Clock::now() + limit;
    while (Clock::now() < deadline && !process::StopRequested()) {
        bool all = true;
        for (const auto& n : names) all = all && heard_.count(n) > 0;
        if (all) return true;
        // Any child that has ended by now failed at start-up, the source included (it only ends
        // by itself once it has run).
        for (Child& c : children_) {
            if (!c.proc->Poll()) continue;
            std::cerr << "gyrocal calibrate: " << c.name << " ended at start-up ("
                      << c.proc->Poll()->Describe() << "); its log " << c.log << ":\n"
                      << TailOf(c.log, 10);
            return false;
        }
        bus_.Handle(50ms);
    }
    for (const auto& n : names)
        if (!heard_.count(n))
            std::cerr << "gyrocal calibrate: no heartbeat from " << n << " within " << limit.count()
                      << " s" << hint << "\n";
    return false;
}

bool Calibration::AwaitPid(const Child& c, std::chrono::seconds limit) {
    const auto deadline = Clock::now() + limit;
    while (Clock::now() < deadline) {
        if (heard_[c.name].count(c.proc->pid())) return true;
        if (c.proc->Poll()) return false;
        bus_.Handle(50ms);
    }
    return false;
}

std::optional<int> Calibration::Supervise() {
    for (Child& c : children_) {
        const std::optional<launch::ExitStatus> how = c.proc->Poll();
        if (!how) continue;
        if (&c == sequencer_ && how->exited && (how->code == 0 || how->code == 3))
            continue;  // it ended the run
        if (&c == source_ && (source_kind_ != Source::kSim || o_.procedure == "rig"))
            continue;  // its end is the data's
        if (ended_at_ || run_ended_) {
            if (&c == sequencer_ || &c == source_) continue;  // stopped after the end of the run
            std::cerr << "\ngyrocal calibrate: " << c.name << " ended after the run ("
                      << how->Describe() << "); log " << c.log << ":\n"
                      << TailOf(c.log, 10);
            return 1;
        }
        if (auto code = HandleCrash(c, *how)) return code;
    }
    return std::nullopt;
}

std::vector<std::string> Calibration::CauseOf(const Child& c) const {
    return ErrorLinesOf(launch::ReadLog(c.log), c.name);
}

std::optional<int> Calibration::HandleCrash(Child& c, const launch::ExitStatus& how) {
    std::cerr << "\ngyrocal calibrate: " << c.name << " ended unexpectedly (" << how.Describe()
              << "); log " << c.log << ":\n"
              << TailOf(c.log, 10);
    const std::string what = c.name + " ended unexpectedly (" + how.Describe() + ")";
    const std::vector<std::string> cause = CauseOf(c);
    if (CrashPolicy(c.name) == OnCrash::kAbortRun) {
        const std::string lost = c.name == "gyrocal-sim-rig"
                                     ? "the simulated chamber and units went with it"
                                     : "its position in the data went with it";
        return AbortRun(
            WithCause(what + ": " + lost + "; a restart would be another experiment", cause));
    }
    if (!budget_.Take(c.name))
        return AbortRun(WithCause(what + " after " + std::to_string(budget_.max()) +
                                      " restarts in this run (--max-restarts)",
                                  cause));
    if (!Restart(c, how))
        return AbortRun(
            WithCause(what + " and did not come back when restarted (log " + c.log + ")", cause));
    return std::nullopt;
}

bool Calibration::Restart(Child& c, const launch::ExitStatus& how) {
    const int previous_pid = c.proc->pid();
    c.previous_cause = CauseOf(c);
    ++c.instance;
    c.log = o_.log_dir + "/" + c.name + "." + std::to_string(c.instance) + ".log";
    std::vector<std::string> argv = c.argv;
    for (const std::string& a : ResumeArgs(c)) argv.push_back(a);
    try {
        c.proc = std::make_unique<launch::ChildProcess>(argv, c.log, c.log);
    } catch (const std::exception& e) {
        std::cerr << "gyrocal calibrate: cannot restart " << c.name << ": " << e.what() << "\n";
        return false;
    }
    if (!AwaitPid(c, 20s)) return false;
    std::cerr << "gyrocal calibrate: restarted " << c.name << " as pid " << c.proc->pid()
              << " (restart " << budget_.used(c.name) << " of " << budget_.max() << "); log "
              << c.log << "\n";
    PublishRestart(c, how, previous_pid);
    return true;
}

std::vector<std::string> Calibration::ResumeArgs(const Child& c) const {
    // A sequencer that dies before its run started simply starts it again.
    if (RecoveryOf(c.name) != Recovery::kResumeSequence || !RunIsOn() || setpoint_index_ < 0 ||
        run_sensors_.empty())
        return {};
    return {"--run-id",
            run_id_,
            "--sensors",
            text::Join(run_sensors_, ","),
            "--resume-setpoint-index",
            std::to_string(setpoint_index_)};
}

void Calibration::PublishRestart(const Child& c, const launch::ExitStatus& how, int previous_pid) {
    if (!RunIsOn()) return;
    static const std::map<Recovery, std::string> kRecovery = {
        {Recovery::kNone, "state from the live bus"},
        {Recovery::kStoredPoints, "the run's plateaus and sensitivity points from the database"},
        {Recovery::kStoredCoeffs, "the newest coefficient set of each sensor from the database"},
        {Recovery::kResumeSequence, "the run resumed at its current setpoint"}};
    const Recovery r = RecoveryOf(c.name);
    run_event_t e;
    e.utime = bus::WallClockUtime();
    e.run_id = run_id_;
    e.event = "restart";
    e.reason =
        WithCause(c.name + " ended unexpectedly (" + how.Describe() + "); restarted as pid " +
                      std::to_string(c.proc->pid()) + " on " + process::HostName() + " (restart " +
                      std::to_string(budget_.used(c.name)) + " of " +
                      std::to_string(budget_.max()) + "); recovery: " + kRecovery.at(r),
                  c.previous_cause);
    e.setpoint_index = setpoint_index_;
    e.setpoint_c = setpoint_index_ >= 0 ? setpoint_c_ : NAN;
    e.num_sensors = 0;
    e.software_version = kSoftwareVersion;
    e.config_json = nlohmann::json{{"process", c.name},
                                   {"pid", c.proc->pid()},
                                   {"previous_pid", previous_pid},
                                   {"ended", how.Describe()},
                                   {"restart", budget_.used(c.name)},
                                   {"max_restarts", budget_.max()},
                                   {"host", process::HostName()}}
                        .dump();
    e.command_line = text::Join(c.proc ? c.argv : std::vector<std::string>{}, " ");
    e.host = process::HostName();
    bus_.Publish(std::string(channels::kRunEvent), e);
}

int Calibration::AbortRun(const std::string& reason) {
    std::cerr << "gyrocal calibrate: aborting the run: " << reason << "\n";
    if (!RunIsOn()) {
        if (run_outcome_.empty()) run_outcome_ = "not started: " + reason;
        return 1;
    }
    run_outcome_ = "abort: " + reason;
    AnnounceRun("abort", reason);
    run_ended_ = true;
    // The sequencer ends by itself on the abort of its run; a signal would record another reason.
    for (int i = 0; i < 60 && sequencer_ && !sequencer_->proc->Poll(); ++i) bus_.Handle(50ms);
    return 3;
}

void Calibration::OnRestartEvent(const run_event_t& e) {
    if (!Runs("gyrocal-recorder")) return;  // the database's host recovers
    const nlohmann::json j = nlohmann::json::parse(e.config_json, nullptr, false);
    if (!j.is_object() || !j.contains("process") || !j["process"].is_string()) return;
    const std::string process = j["process"].get<std::string>();
    const Recovery r = RecoveryOf(process);
    if (r == Recovery::kStoredPoints || r == Recovery::kStoredCoeffs)
        recoveries_.push_back({Clock::now() + kRecoveryDelay, r, e.run_id, process});
}

void Calibration::RecoverDue() {
    for (auto it = recoveries_.begin(); it != recoveries_.end();) {
        if (Clock::now() < it->due) {
            ++it;
            continue;
        }
        try {
            if (!services_.recovery)
                throw std::runtime_error("this launcher was given no database reader (store)");
            const RecoveredState r = services_.recovery(o_.db, it->run_id);
            size_t n = 0;
            if (it->what == Recovery::kStoredPoints) {
                for (const auto& p : r.plateaus)
                    n += bus_.Publish(channels::Plateau(p.sensor_id), p) ? 1 : 0;
                for (const auto& s : r.rotations)
                    n += bus_.Publish(channels::Sensitivity(s.sensor_id), s) ? 1 : 0;
            } else {
                for (const auto& c : r.newest_coeffs)
                    n += bus_.Publish(channels::Coeffs(c.sensor_id), c) ? 1 : 0;
            }
            std::cerr << "gyrocal calibrate: recovered " << it->process << ": published " << n
                      << (it->what == Recovery::kStoredPoints ? " plateaus and sensitivity points"
                                                              : " coefficient sets")
                      << " of run " << it->run_id << " from " << o_.db << "\n";
        } catch (const std::exception& e) {
            std::cerr << "gyrocal calibrate: cannot recover " << it->process << " from " << o_.db
                      << ": " << e.what() << " (it goes on from the live bus only)\n";
        }
        it = recoveries_.erase(it);
    }
}

void Calibration::StopAll() {
    // Source first (no new data), then processors, recorder last so it can flush what they sent.
    if (source_) source_->proc->Stop();
    if (sequencer_) sequencer_->proc->Stop();
    for (auto& c : children_)
        if (c.name != "gyrocal-recorder") c.proc->Stop();
    for (int i = 0; i < 10; ++i) bus_.Handle(20ms);  // let the last heartbeats arrive
    for (auto& c : children_)
        if (c.name == "gyrocal-recorder") {
            launch::ExitStatus s = c.proc->Stop(std::chrono::milliseconds(15000));
            if (!s.exited || s.code != 0)
                std::cerr << "gyrocal calibrate: recorder ended with " << s.Describe() << "; log "
                          << c.log << "\n";
        }
}

}  // namespace gyrocal::supervisor
