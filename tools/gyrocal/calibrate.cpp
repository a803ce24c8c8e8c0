#include "calibrate.hpp"

#include <unistd.h>

#include <csignal>

#include <chrono>
#include <cmath>
#include <deque>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "bus/bus.hpp"
#include "bus/channels.hpp"
#include "bus/shutdown.hpp"
#include "bus/status.hpp"
#include "coeff_table.hpp"
#include "final_verdict.hpp"
#include "gyrocal/chamber_state_t.hpp"
#include "gyrocal/coeff_set_t.hpp"
#include "gyrocal/fit_report_t.hpp"
#include "gyrocal/plateau_state_t.hpp"
#include "gyrocal/run_event_t.hpp"
#include "gyrocal/sensitivity_point_t.hpp"
#include "gyrocal/status_t.hpp"
#include "gyrocal/version.hpp"
#include "launch/child_process.hpp"
#include "paths.hpp"
#include "procedure.hpp"
#include "progress.hpp"
#include "sim/config.hpp"
#include "sim/noise.hpp"

namespace gyrocal::cli {

double PlateauSlowNoiseOfSimulatedGyroDps(double average_s) {
    // Over about an hour of run (the rate random walk's share grows with it; ~1 % here).
    return std::sqrt(sim::SlowNoiseBinVariance(sim::NoiseConfig{}, average_s, 3600.0));
}

double EffectivePlateauSlowNoiseDps(const CalibrateOptions& o) {
    if (o.plateau_slow_noise_dps >= 0.0) return o.plateau_slow_noise_dps;
    return o.source == "sim" ? PlateauSlowNoiseOfSimulatedGyroDps() : -1.0;
}
namespace {

using Clock = std::chrono::steady_clock;
using namespace std::chrono_literals;

double SecondsSince(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

std::string TailOf(const std::string& path, int lines) {
    std::ifstream f(path);
    std::vector<std::string> all;
    for (std::string l; std::getline(f, l);) all.push_back(l);
    std::string out;
    for (size_t i = all.size() > static_cast<size_t>(lines) ? all.size() - lines : 0; i < all.size(); ++i)
        out += "    " + all[i] + "\n";
    return out;
}

class Calibration {
public:
    explicit Calibration(CalibrateOptions o) : o_(std::move(o)), bus_(BusOptions{o_.lcm_url}) {
        url_ = bus_.url();
        if (o_.log_dir.empty()) {
            const char* tmp = std::getenv("TMPDIR");
            o_.log_dir = std::string(tmp && *tmp ? tmp : "/tmp") + "/gyrocal-calibrate-" + std::to_string(getpid());
        }
        std::filesystem::create_directories(o_.log_dir);
        if (o_.truth_out.empty()) o_.truth_out = o_.log_dir + "/truth.json";
        Subscribe();
    }

    int Run();

private:
    struct Child {
        std::string name;
        std::string log;
        std::unique_ptr<ChildProcess> proc;
    };

    void Subscribe();
    Child& Start(const std::string& exe, std::vector<std::string> args);
    bool AwaitHeartbeats(const std::set<std::string>& names, std::chrono::seconds limit);
    std::string ConfigJson() const;
    void AnnounceRun(const std::string& event, const std::string& reason);
    void ShowProgress(bool force);
    const Child* DeadChild();  // a child that ended although it should still run
    void StopAll();
    std::set<std::string> Sensors() const;
    bool HaveFinalCoeffs() const;
    int Finish(int code);

    CalibrateOptions o_;
    Bus bus_;
    std::string url_;
    std::deque<Child> children_;  // deque: Start() hands out references that must stay valid
    Child* sequencer_ = nullptr;
    Child* source_ = nullptr;
    std::set<std::string> heard_;  // process names seen in STATUS
    std::unique_ptr<Progress> progress_;
    std::vector<std::string> run_sensors_;
    std::set<std::string> stability_sensors_;
    std::map<std::string, coeff_set_t> coeffs_;        // newest per sensor
    std::set<std::string> final_coeffs_;               // sensors with a set after the stop
    std::map<std::string, fit_report_t> final_reports_;  // the fitter's verdict at the stop
    bool stop_seen_ = false;
    std::string run_id_;
    std::string run_outcome_;
    Clock::time_point start_ = Clock::now();
    Clock::time_point last_line_{};
};

void Calibration::Subscribe() {
    bus_.Subscribe<status_t>(std::string(channels::kStatus), [this](const status_t& s, const std::string&) {
        heard_.insert(s.process);
        if (progress_) progress_->OnStatus(s);
    });
    bus_.Subscribe<run_event_t>(std::string(channels::kRunEvent), [this](const run_event_t& e, const std::string&) {
        if (progress_) progress_->OnRunEvent(e);
        run_id_ = e.run_id;
        if (!e.sensor_ids.empty()) run_sensors_ = e.sensor_ids;
        if (e.event == "stop" || e.event == "abort") {
            stop_seen_ = true;
            run_outcome_ = e.event + ": " + e.reason;
        }
    });
    bus_.Subscribe<chamber_state_t>(std::string(channels::kChamberState),
                                    [this](const chamber_state_t& s, const std::string&) {
                                        if (progress_) progress_->OnChamber(s);
                                    });
    bus_.Subscribe<plateau_state_t>(channels::AllSensors(channels::kStabilityPrefix),
                                    [this](const plateau_state_t& s, const std::string&) {
                                        stability_sensors_.insert(s.sensor_id);
                                        if (progress_) progress_->OnStability(s);
                                    });
    bus_.Subscribe<sensitivity_point_t>(channels::AllSensors(channels::kSensitivityPrefix),
                                        [this](const sensitivity_point_t& s, const std::string&) {
                                            if (progress_) progress_->OnSensitivity(s);
                                        });
    bus_.Subscribe<fit_report_t>(channels::AllSensors(channels::kFitPrefix),
                                 [this](const fit_report_t& r, const std::string&) {
                                     if (r.is_final) final_reports_[r.sensor_id] = r;
                                 });
    bus_.Subscribe<coeff_set_t>(channels::AllSensors(channels::kCoeffsPrefix),
                                [this](const coeff_set_t& c, const std::string&) {
                                    coeffs_[c.sensor_id] = c;
                                    if (stop_seen_) final_coeffs_.insert(c.sensor_id);
                                    if (progress_) progress_->OnCoeffs(c);
                                });
}

Calibration::Child& Calibration::Start(const std::string& exe, std::vector<std::string> args) {
    Child c;
    c.name = std::filesystem::path(exe).filename().string();
    c.log = o_.log_dir + "/" + c.name + ".log";
    args.insert(args.begin(), exe);
    c.proc = std::make_unique<ChildProcess>(args, c.log, c.log);
    children_.push_back(std::move(c));
    return children_.back();
}

bool Calibration::AwaitHeartbeats(const std::set<std::string>& names, std::chrono::seconds limit) {
    const auto deadline = Clock::now() + limit;
    while (Clock::now() < deadline && !StopRequested()) {
        bool all = true;
        for (const auto& n : names) all = all && heard_.count(n) > 0;
        if (all) return true;
        // Any child that has ended by now failed at start-up, the source included (it only ends
        // by itself once it has run).
        for (const Child& c : children_) {
            if (!c.proc->Poll()) continue;
            std::cerr << "gyrocal calibrate: " << c.name << " ended at start-up (" << c.proc->Poll()->Describe()
                      << "); its log " << c.log << ":\n"
                      << TailOf(c.log, 10);
            return false;
        }
        bus_.Handle(50ms);
    }
    for (const auto& n : names)
        if (!heard_.count(n)) std::cerr << "gyrocal calibrate: no heartbeat from " << n << " within " << limit.count() << " s\n";
    return false;
}

std::string Calibration::ConfigJson() const {
    nlohmann::json j;
    j["source"] = o_.source;
    j["input"] = o_.input;
    j["db"] = o_.db;
    j["lcm_url"] = url_;
    j["sensors"] = o_.sensors;
    j["preset"] = o_.preset;
    j["seed"] = o_.seed;
    j["noise_seed"] = o_.noise_seed;
    j["plateau_slow_noise_dps"] = EffectivePlateauSlowNoiseDps(o_);
    j["speed"] = o_.speed;
    j["profile"] = o_.profile;
    j["setpoints_c"] = o_.setpoints_c;
    j["effects"] = o_.effects;
    j["args"] = {{"rig", o_.rig_args},           {"plateau", o_.plateau_args},
                 {"rotation", o_.rotation_args}, {"fitter", o_.fitter_args},
                 {"compensator", o_.compensator_args}, {"sequencer", o_.sequencer_args},
                 {"recorder", o_.recorder_args}, {"source", o_.source_args}};
    return j.dump();
}

void Calibration::AnnounceRun(const std::string& event, const std::string& reason) {
    // Measured data has no sequencer: the launcher owns the run and announces it itself.
    run_event_t e;
    e.utime = std::chrono::duration_cast<std::chrono::microseconds>(
                  std::chrono::system_clock::now().time_since_epoch()).count();
    if (run_id_.empty()) {
        char buf[32];
        std::time_t t = std::time(nullptr);
        std::strftime(buf, sizeof buf, "%Y%m%dT%H%M%SZ", std::gmtime(&t));
        run_id_ = std::string(buf) + "-" + HostName() + "-" + std::to_string(getpid());
    }
    e.run_id = run_id_;
    e.event = event;
    e.reason = reason;
    e.setpoint_index = -1;
    e.setpoint_c = NAN;
    e.num_sensors = 0;
    e.software_version = kSoftwareVersion;
    e.config_json = ConfigJson();
    e.command_line = o_.command_line;
    e.host = HostName();
    bus_.Publish(std::string(channels::kRunEvent), e);
}

const Calibration::Child* Calibration::DeadChild() {
    for (auto& c : children_) {
        if (&c == sequencer_ || &c == source_) continue;  // these end by themselves
        if (c.proc->Poll()) return &c;
    }
    return nullptr;
}

void Calibration::ShowProgress(bool force) {
    if (o_.quiet || !progress_) return;
    const bool tty = isatty(STDOUT_FILENO);
    const auto period = tty ? 500ms : 10s;
    if (!force && Clock::now() - last_line_ < period) return;
    last_line_ = Clock::now();
    std::string line = progress_->Line(SecondsSince(start_));
    if (tty) {
        if (line.size() > 200) line.resize(200);
        std::cout << "\r\033[K" << line << std::flush;
    } else {
        std::cout << line << "\n" << std::flush;
    }
}

std::set<std::string> Calibration::Sensors() const {
    if (!run_sensors_.empty()) return {run_sensors_.begin(), run_sensors_.end()};
    std::set<std::string> s = stability_sensors_;
    for (const auto& [id, c] : coeffs_) s.insert(id);
    return s;
}

bool Calibration::HaveFinalCoeffs() const {
    const auto sensors = Sensors();
    if (sensors.empty()) return false;
    // The fitter's final report follows each final set (and says "none" when there is no set).
    for (const auto& s : sensors)
        if (!final_reports_.count(s)) return false;
    return true;
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
            ExitStatus s = c.proc->Stop(std::chrono::milliseconds(15000));
            if (!s.exited || s.code != 0)
                std::cerr << "gyrocal calibrate: recorder ended with " << s.Describe() << "; log " << c.log << "\n";
        }
}

int Calibration::Run() {
    const std::string url_arg = url_;
    auto common = [&](std::vector<std::string> extra, const std::vector<std::string>& pass) {
        std::vector<std::string> a = {"--lcm-url", url_arg};
        a.insert(a.end(), extra.begin(), extra.end());
        a.insert(a.end(), pass.begin(), pass.end());
        return a;
    };
    std::cout << "gyrocal calibrate: logs in " << o_.log_dir << ", database " << o_.db << ", LCM " << url_ << "\n";
    try {
        Start(SiblingExecutable("gyrocal-recorder"), common({"--db", o_.db}, o_.recorder_args));
        Start(SiblingExecutable("gyrocal-plateau"), common({}, o_.plateau_args));
        Start(SiblingExecutable("gyrocal-rotation"), common({}, o_.rotation_args));
        std::vector<std::string> fitter;
        if (EffectivePlateauSlowNoiseDps(o_) >= 0)
            fitter = {"--plateau-slow-noise-dps", std::to_string(EffectivePlateauSlowNoiseDps(o_))};
        if (o_.source == "sim")
            fitter.insert(fitter.end(), {"--nominal-sensitivity-v-per-dps",
                                         std::to_string(sim::PresetByName(o_.preset).sensitivity_v_per_dps)});
        Start(SiblingExecutable("gyrocal-fitter"), common(fitter, o_.fitter_args));
        Start(SiblingExecutable("gyrocal-compensator"), common({}, o_.compensator_args));
    } catch (const std::exception& e) {
        std::cerr << "gyrocal calibrate: " << e.what() << " (is the project built? tools/run.sh setup)\n";
        return Finish(1);
    }
    if (!AwaitHeartbeats({"gyrocal-recorder", "gyrocal-plateau", "gyrocal-rotation", "gyrocal-fitter",
                          "gyrocal-compensator"},
                         20s))
        return Finish(1);

    const auto named = sequencer::NamedProfile(o_.profile);
    int setpoints = static_cast<int>(o_.setpoints_c.empty() ? (named ? named->setpoints_c.size() : 0)
                                                            : o_.setpoints_c.size());
    try {
        if (o_.source == "sim") {
            progress_ = std::make_unique<Progress>(setpoints, 2);
            const double speed = o_.speed > 0 ? o_.speed : kAutoRigMessagesPerS / (100.0 * (o_.sensors + 1));
            std::vector<std::string> rig = {"--mode", "commanded", "--units", std::to_string(o_.sensors),
                                            "--preset", o_.preset, "--seed", std::to_string(o_.seed),
                                            "--noise-seed", std::to_string(o_.noise_seed),
                                            "--speed", std::to_string(speed), "--truth-out", o_.truth_out};
            for (const auto& e : o_.effects) {
                rig.push_back("--effect");
                rig.push_back(e);
            }
            source_ = &Start(SiblingExecutable("gyrocal-sim-rig"), common(rig, o_.rig_args));
            if (!AwaitHeartbeats({"gyrocal-sim-rig"}, 20s)) return Finish(1);
            std::vector<std::string> seq = {"--run-config-json", ConfigJson(), "--command-line", o_.command_line};
            if (!o_.setpoints_c.empty()) {
                std::string list;
                for (double t : o_.setpoints_c) list += (list.empty() ? "" : ",") + std::to_string(t);
                seq.insert(seq.end(), {"--setpoints-c", list});
            } else {
                seq.insert(seq.end(), {"--profile", o_.profile});
            }
            sequencer_ = &Start(SiblingExecutable("gyrocal-sequencer"), common(seq, o_.sequencer_args));
        } else {
            progress_ = std::make_unique<Progress>(0, 0);
            AnnounceRun("start", "measured data from " + o_.source + (o_.input.empty() ? "" : " " + o_.input));
            if (o_.source == "csv") {
                // A file is replayed as fast as the pipeline keeps up (the source's own lossless
                // cap) unless the caller chose a pace.
                std::vector<std::string> pace;
                if (o_.source_args.empty()) pace = {"--max"};
                pace.insert(pace.begin(), o_.input);
                source_ = &Start(SiblingExecutable("gyrocal-csv-source"), common(pace, o_.source_args));
            } else if (o_.source == "lines") {
                source_ = &Start(SiblingExecutable("gyrocal-line-source"), common({}, o_.source_args));
            } else {  // log
                std::vector<std::string> a = {"--lcm-url=" + url_arg};
                a.insert(a.end(), o_.source_args.begin(), o_.source_args.end());
                a.push_back(o_.input);
                source_ = &Start("lcm-logplayer", a);
            }
        }
    } catch (const std::exception& e) {
        std::cerr << "gyrocal calibrate: " << e.what() << "\n";
        return Finish(1);
    }

    // Main watch loop: until the run has ended and every sensor's final coefficients arrived.
    std::optional<Clock::time_point> ended_at;
    while (true) {
        bus_.Handle(50ms);
        ShowProgress(false);
        if (StopRequested()) {
            std::cout << "\ngyrocal calibrate: interrupted; stopping the run\n";
            if (sequencer_) sequencer_->proc->Signal(SIGTERM);  // it records the abort
            if (!sequencer_) AnnounceRun("abort", "operator stop (signal)");
            for (int i = 0; i < 40 && sequencer_ && !sequencer_->proc->Poll(); ++i) bus_.Handle(50ms);
            run_outcome_ = "abort: operator stop";
            return Finish(3);
        }
        if (const Child* dead = DeadChild()) {
            std::cerr << "\ngyrocal calibrate: " << dead->name << " ended unexpectedly (" << dead->proc->Poll()->Describe()
                      << "); log " << dead->log << ":\n" << TailOf(dead->log, 10);
            if (!sequencer_) AnnounceRun("abort", dead->name + " failed");
            return Finish(1);
        }
        if (!ended_at) {
            if (sequencer_ && sequencer_->proc->Poll()) ended_at = Clock::now();
            if (!sequencer_ && source_->proc->Poll()) {
                const ExitStatus s = *source_->proc->Poll();
                // Let the processors drain what the source published before closing the run.
                for (int i = 0; i < 20; ++i) bus_.Handle(50ms);
                AnnounceRun(s.exited && s.code == 0 ? "stop" : "abort",
                            s.exited && s.code == 0 ? "end of data" : o_.source + " source " + s.Describe());
                ended_at = Clock::now();
            }
        } else {
            if (HaveFinalCoeffs()) break;
            if (SecondsSince(*ended_at) > o_.final_coeffs_wait_s) {
                std::cerr << "\ngyrocal calibrate: no final coefficient set within " << o_.final_coeffs_wait_s
                          << " s from every sensor\n";
                break;
            }
        }
        if (o_.wall_timeout_s > 0 && SecondsSince(start_) > o_.wall_timeout_s) {
            std::cerr << "\ngyrocal calibrate: wall-clock limit of " << o_.wall_timeout_s << " s reached\n";
            if (sequencer_) sequencer_->proc->Signal(SIGTERM);
            for (int i = 0; i < 40 && sequencer_ && !sequencer_->proc->Poll(); ++i) bus_.Handle(50ms);
            run_outcome_ = "abort: wall-clock limit";
            return Finish(3);
        }
    }
    ShowProgress(true);
    std::cout << "\n";
    int code = 0;
    if (sequencer_) {
        const ExitStatus s = *sequencer_->proc->Poll();
        if (!s.exited || s.code != 0) code = 3;
    }
    if (run_outcome_.rfind("stop", 0) != 0) code = 3;
    if (!HaveFinalCoeffs()) code = 3;
    if (!FinalVerdict{Sensors(), coeffs_, final_coeffs_, final_reports_}.AllComplete()) code = 3;
    return Finish(code);
}

int Calibration::Finish(int code) {
    StopAll();
    std::cout << "\nrun " << (run_id_.empty() ? "(none)" : run_id_) << ": "
              << (run_outcome_.empty() ? "not finished" : run_outcome_) << "\n";
    if (progress_) std::cout << "losses seen on the bus (sequence gaps + decode errors + queue drops): " << progress_->drops() << "\n";
    if (!coeffs_.empty()) {
        std::cout << "\n" << FormatCoeffTable(coeffs_, FinalVerdict{Sensors(), coeffs_, final_coeffs_, final_reports_}.Labels());
        std::ifstream truth(o_.truth_out);
        if (truth && o_.source == "sim") {
            try {
                std::cout << "\n" << FormatTruthComparison(coeffs_, nlohmann::json::parse(truth));
            } catch (const std::exception& e) {
                std::cerr << "gyrocal calibrate: cannot compare with the truth in " << o_.truth_out << ": " << e.what() << "\n";
            }
        }
    }
    std::cout << "\ndatabase: " << o_.db << "   logs: " << o_.log_dir << "\n";
    if (stop_seen_)
        std::cerr << FinalVerdict{Sensors(), coeffs_, final_coeffs_, final_reports_}.Explain();
    return code;
}

}  // namespace

int RunCalibration(const CalibrateOptions& options) {
    InstallStopHandlers();
    CalibrateOptions o = options;
    if (o.command_line.empty()) {
        // The command line as the kernel has it (NUL-separated), recorded with the run.
        std::ifstream f("/proc/self/cmdline");
        for (std::string arg; std::getline(f, arg, '\0');) o.command_line += (o.command_line.empty() ? "" : " ") + arg;
    }
    try {
        Calibration c(o);
        return c.Run();
    } catch (const BusError& e) {
        std::cerr << "gyrocal calibrate: " << e.what() << "\n";
        return 1;
    } catch (const std::exception& e) {
        std::cerr << "gyrocal calibrate: " << e.what() << "\n";
        return 1;
    }
}

}  // namespace gyrocal::cli
