#include "tools/supervisor/launcher.hpp"

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <deque>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "gyrocal/analysis_t.hpp"
#include "gyrocal/chamber_state_t.hpp"
#include "gyrocal/coeff_set_t.hpp"
#include "gyrocal/fit_report_t.hpp"
#include "gyrocal/plateau_state_t.hpp"
#include "gyrocal/run_event_t.hpp"
#include "gyrocal/sensitivity_point_t.hpp"
#include "gyrocal/status_t.hpp"
#include "gyrocal/version.hpp"
#include "lcmtypes/bus/batch.hpp"
#include "lcmtypes/bus/bus.hpp"
#include "lcmtypes/channels/channels.hpp"
#include "lcmtypes/launch/child_process.hpp"
#include "lcmtypes/process/process_main.hpp"
#include "lcmtypes/process/shutdown.hpp"
#include "lcmtypes/process/status.hpp"
#include "lcmtypes/text/join.hpp"
#include "processors/model/convert.hpp"
#include "processors/model/json.hpp"
#include "processors/sequencer/procedure.hpp"
#include "producers/csv/file_digest.hpp"
#include "tools/supervisor/child_errors.hpp"
#include "tools/supervisor/coeff_table.hpp"
#include "tools/supervisor/final_verdict.hpp"
#include "tools/supervisor/input_check.hpp"
#include "tools/supervisor/paths.hpp"
#include "tools/supervisor/progress.hpp"
#include "tools/supervisor/supervisor.hpp"

namespace gyrocal::supervisor {

std::vector<std::string> SourceNames() {
    std::vector<std::string> names;
    for (const SourceName& s : kSourceNames) names.emplace_back(s.name);
    return names;
}

Source ParseSource(const std::string& name) {
    for (const SourceName& s : kSourceNames)
        if (name == s.name) return s.source;
    std::string valid;
    for (const SourceName& s : kSourceNames)
        valid += (valid.empty() ? "" : ", ") + std::string(s.name);
    throw std::invalid_argument("--source '" + name + "' is not valid: use " + valid);
}

double EffectivePlateauSlowNoiseDps(const CalibrateOptions& o) {
    if (o.plateau_slow_noise_dps >= 0.0) return o.plateau_slow_noise_dps;
    return ParseSource(o.source) == Source::kSim ? o.simulated.plateau_slow_noise_dps : -1.0;
}
double SecondsSince(Clock::time_point t0) {
    return std::chrono::duration<double>(Clock::now() - t0).count();
}

std::string TailOf(const std::string& path, int lines) {
    std::ifstream f(path);
    std::vector<std::string> all;
    for (std::string l; std::getline(f, l);) all.push_back(l);
    std::string out;
    for (size_t i = all.size() > static_cast<size_t>(lines) ? all.size() - lines : 0;
         i < all.size(); ++i)
        out += "    " + all[i] + "\n";
    return out;
}

std::string EffectiveLcmUrl(const CalibrateOptions& o) {
    return ChamberUrl(bus::BusOptions{o.lcm_url}.ResolvedUrl(), o.chamber);
}

namespace {

using namespace std::chrono_literals;

// True when the source's own arguments already set its pace (--speed, --max or a batch size).
bool PaceGiven(const std::vector<std::string>& args) {
    for (const std::string& a : args)
        for (const char* opt : {"--speed", "--max", "--batch-samples"})
            if (a == opt || a.rfind(std::string(opt) + "=", 0) == 0) return true;
    return false;
}

// The consumers the producers must hear before publishing anything, so that no sample is missed.
const std::set<std::string> kConsumers = {"gyrocal-recorder", "gyrocal-plateau", "gyrocal-rotation",
                                          "gyrocal-fitter", "gyrocal-compensator"};

}  // namespace

Calibration::Calibration(CalibrateOptions o, StoreServices services)
    : o_(std::move(o)),
      services_(std::move(services)),
      source_kind_(ParseSource(o_.source)),
      role_(*ParseRole(o_.role)),
      bus_(bus::BusOptions{o_.lcm_url}),
      acker_(bus_, "gyrocal calibrate"),
      budget_(o_.max_restarts) {
    url_ = bus_.url();
    if (o_.log_dir.empty()) {
        const char* tmp = std::getenv("TMPDIR");
        o_.log_dir = std::string(tmp && *tmp ? tmp : "/tmp") + "/gyrocal-calibrate-" +
                     std::to_string(getpid());
    }
    std::filesystem::create_directories(o_.log_dir);
    if (o_.truth_out.empty()) o_.truth_out = o_.log_dir + "/truth.json";
    // Which measured data the run was made from, recorded with it (gyrocal report shows it).
    if (ReadsInputFile(source_kind_)) input_sha256_ = csv::Sha256HexOfFile(o_.input);
    Subscribe();
}

void Calibration::Subscribe() {
    bus_.Subscribe<status_t>(std::string(channels::kStatus),
                             [this](const status_t& s, const std::string&) {
                                 heard_[s.process].insert(s.pid);
                                 if (progress_) progress_->OnStatus(s);
                             });
    bus_.Subscribe<run_event_t>(
        std::string(channels::kRunEvent),
        [this](const run_event_t& e, const std::string&) { OnRunEvent(e); });
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
                                     if (!r.is_final) return;
                                     if (r.source == model::kClosedLoopSource)
                                         loop_reports_[r.sensor_id] = r;
                                     else
                                         final_reports_[r.sensor_id] = r;
                                 });
    bus_.Subscribe<analysis_t>(channels::AllSensors(channels::kAnalysisPrefix),
                               [this](const analysis_t& a, const std::string&) {
                                   if (a.is_final) loop_analyses_[a.sensor_id] = a;
                               });
    bus_.Subscribe<coeff_set_t>(channels::AllSensors(channels::kCoeffsPrefix),
                                [this](const coeff_set_t& c, const std::string&) {
                                    if (c.source == model::kFitterSource)
                                        plateau_sets_[c.sensor_id] = c;
                                    coeffs_[c.sensor_id] = c;
                                    if (stop_seen_) final_coeffs_.insert(c.sensor_id);
                                    if (progress_) progress_->OnCoeffs(c);
                                });
}

void Calibration::OnRunEvent(const run_event_t& e) {
    // This launcher's run is the first one it sees begin (or, on a host started late, go on);
    // events of any other run are someone else's.
    if (run_id_.empty() && (e.event == "stop" || e.event == "abort")) return;
    if (!run_id_.empty() && e.run_id != run_id_) return;
    run_id_ = e.run_id;
    if (progress_) progress_->OnRunEvent(e);
    if (!e.sensor_ids.empty()) run_sensors_ = e.sensor_ids;
    if (e.event == "setpoint") {
        setpoint_index_ = e.setpoint_index;
        setpoint_c_ = e.setpoint_c;
    } else if (e.event == "restart") {
        OnRestartEvent(e);
    } else if (e.event == "stop" || e.event == "abort") {
        stop_seen_ = run_ended_ = true;
        run_outcome_ = e.event + ": " + e.reason;
    }
}

bool Calibration::StartConsumers() {
    std::set<std::string> local;
    auto start = [&](const std::string& exe, std::vector<std::string> args,
                     const std::vector<std::string>& pass) {
        if (!Runs(exe)) return;
        args.insert(args.end(), pass.begin(), pass.end());
        Start(SiblingExecutable(exe), args);
        local.insert(exe);
    };
    try {
        start("gyrocal-recorder", {"--db", o_.db}, o_.recorder_args);
        start("gyrocal-plateau", {}, o_.plateau_args);
        start("gyrocal-rotation", {}, o_.rotation_args);
        std::vector<std::string> fitter;
        if (EffectivePlateauSlowNoiseDps(o_) >= 0)
            fitter = {"--plateau-slow-noise-dps", std::to_string(EffectivePlateauSlowNoiseDps(o_))};
        if (source_kind_ == Source::kSim && o_.simulated.nominal_sensitivity_v_per_dps > 0)
            fitter.insert(fitter.end(),
                          {"--nominal-sensitivity-v-per-dps",
                           std::to_string(o_.simulated.nominal_sensitivity_v_per_dps)});
        if (IsRamp()) fitter.insert(fitter.end(), {"--mode", "ramp"});
        // The seed's 3-point procedure keeps its own method: no closed loop beside it.
        if (!IsRamp() && !ClosedLoop()) fitter.insert(fitter.end(), {"--closed-loop", "false"});
        start("gyrocal-fitter", fitter, o_.fitter_args);
        start("gyrocal-compensator", {}, o_.compensator_args);
    } catch (const std::exception& e) {
        std::cerr << "gyrocal calibrate: " << e.what()
                  << " (is the project built? tools/run.sh setup)\n";
        return false;
    }
    return local.empty() || AwaitHeartbeats(local, 20s, "");
}

bool Calibration::StartProducers() {
    // Every consumer must listen before the first sample: on other hosts they are the other roles.
    const std::string hint =
        role_ == Role::kAll ? ""
                            : " (start `gyrocal calibrate --role processors` and `--role recorder` "
                              "on their hosts first, on the same LCM URL)";
    if (!AwaitHeartbeats(kConsumers,
                         std::chrono::seconds(static_cast<int64_t>(std::ceil(o_.await_peers_s))),
                         hint))
        return false;
    try {
        if (source_kind_ == Source::kSim) {
            StartSim();
        } else {
            StartMeasured();
        }
    } catch (const std::exception& e) {
        std::cerr << "gyrocal calibrate: " << e.what() << "\n";
        return false;
    }
    return source_kind_ != Source::kSim || AwaitHeartbeats({"gyrocal-sim-rig"}, 20s, "");
}

// How a non-real-time source is paced: auto (--speed 0) batches the samples and lets the graph
// set the pace (flow control); a given --speed is the rig's fixed speed, samples alone.
std::vector<std::string> Calibration::SimPace() const {
    if (o_.speed > 0) return {"--speed", std::to_string(o_.speed)};
    return {"--speed", "0", "--batch-samples", std::to_string(bus::kDefaultBatchSamples)};
}

void Calibration::StartSim() {
    std::vector<std::string> rig = {"--units",      std::to_string(o_.sensors),
                                    "--preset",     o_.preset,
                                    "--seed",       std::to_string(o_.seed),
                                    "--noise-seed", std::to_string(o_.noise_seed),
                                    "--truth-out",  o_.truth_out};
    const std::vector<std::string> pace = SimPace();
    rig.insert(rig.end(), pace.begin(), pace.end());
    for (const auto& e : o_.effects) rig.insert(rig.end(), {"--effect", e});
    std::vector<std::string> setpoints;
    for (double t : o_.setpoints_c) setpoints.push_back(std::to_string(t));
    if (o_.procedure == "rig") {
        // The rig runs the profile itself, on data time only: the same seed gives the same run.
        if (setpoints.empty())
            if (const auto p = sequencer::NamedProfile(o_.profile))
                for (double t : p->setpoints_c) setpoints.push_back(std::to_string(t));
        rig.insert(rig.end(), {"--mode", "builtin", "--profile", text::Join(setpoints, ",")});
        AnnounceRun("start", "the simulated rig's own procedure (profile " +
                                 text::Join(setpoints, ",") + ")");
        rig.insert(rig.end(), o_.rig_args.begin(), o_.rig_args.end());
        source_ = &Start(SiblingExecutable("gyrocal-sim-rig"), rig);
        return;
    }
    rig.insert(rig.end(), {"--mode", "commanded"});
    rig.insert(rig.end(), o_.rig_args.begin(), o_.rig_args.end());
    source_ = &Start(SiblingExecutable("gyrocal-sim-rig"), rig);
    if (!AwaitHeartbeats({"gyrocal-sim-rig"}, 20s, ""))
        throw std::runtime_error("the rig did not start");
    std::vector<std::string> seq = {"--run-config-json", ConfigJson(), "--command-line",
                                    o_.command_line,     "--profile",  o_.profile};
    if (!setpoints.empty()) seq.insert(seq.end(), {"--setpoints-c", text::Join(setpoints, ",")});
    if (o_.ramp_rate_c_per_min > 0)
        seq.insert(seq.end(), {"--ramp-rate-c-per-min", std::to_string(o_.ramp_rate_c_per_min)});
    if (IsRamp()) {
        if (!o_.ramp_range_c.empty())
            seq.insert(seq.end(), {"--ramp-range-c", std::to_string(o_.ramp_range_c.at(0)) + "," +
                                                         std::to_string(o_.ramp_range_c.at(1))});
        seq.insert(seq.end(), {"--turn-interval-s", std::to_string(o_.turn_interval_s), "--dwell-s",
                               std::to_string(o_.dwell_s), "--target-offset-dps",
                               std::to_string(o_.target_offset_dps), "--target-sensitivity-pct",
                               std::to_string(o_.target_sensitivity_pct)});
    }
    seq.insert(seq.end(), o_.sequencer_args.begin(), o_.sequencer_args.end());
    sequencer_ = &Start(SiblingExecutable("gyrocal-sequencer"), seq);
}

void Calibration::StartMeasured() {
    AnnounceRun("start",
                "measured data from " + o_.source + (o_.input.empty() ? "" : " " + o_.input));
    switch (source_kind_) {
        case Source::kCsv: {
            // A file is replayed as fast as every process of the graph keeps up (flow control),
            // its samples batched, unless the caller chose a pace.
            std::vector<std::string> pace;
            if (!PaceGiven(o_.source_args))
                pace = {"--max", "--batch-samples", std::to_string(bus::kDefaultBatchSamples)};
            pace.insert(pace.begin(), o_.input);
            pace.insert(pace.end(), o_.source_args.begin(), o_.source_args.end());
            source_ = &Start(SiblingExecutable("gyrocal-csv-source"), pace);
            break;
        }
        case Source::kLines:
            source_ = &Start(SiblingExecutable("gyrocal-line-source"), o_.source_args);
            break;
        case Source::kLog: {  // like a CSV file: as fast as the graph keeps up unless paced
            std::vector<std::string> a = {o_.input};
            if (!PaceGiven(o_.source_args)) a.push_back("--max");
            a.insert(a.end(), o_.source_args.begin(), o_.source_args.end());
            source_ = &Start(SiblingExecutable("gyrocal-log-source"), a);
            break;
        }
        case Source::kSim:
            throw std::logic_error("StartMeasured: the simulated rig is not measured data");
    }
}

bool Calibration::IsRamp() const {
    const auto p = sequencer::NamedProfile(o_.profile);
    return p && p->continuous;
}

std::string Calibration::ConfigJson() const {
    nlohmann::json j =
        GYROCAL_JSON_FIELDS(o_, source, input, db, role, chamber, procedure, sensors, preset, seed,
                            noise_seed, speed, profile, setpoints_c, effects, max_restarts);
    j["lcm_url"] = url_;
    j["plateau_slow_noise_dps"] = EffectivePlateauSlowNoiseDps(o_);
    if (IsRamp())
        j.update(GYROCAL_JSON_FIELDS(o_, ramp_range_c, turn_interval_s, dwell_s, target_offset_dps,
                                     target_sensitivity_pct));
    if (o_.ramp_rate_c_per_min > 0) j["ramp_rate_c_per_min"] = o_.ramp_rate_c_per_min;
    if (!input_sha256_.empty()) j["input_sha256"] = input_sha256_;
    if (!o_.limits_json.empty()) {
        j["acceptance_limits"] = nlohmann::json::parse(o_.limits_json);
        j["acceptance_limits_file"] = o_.limits_file;
    }
    nlohmann::json& args = j["args"] = nlohmann::json::object();
    for (const ChildArgs& c : kChildArgs) args[c.name] = o_.*c.args;
    return j.dump();
}

void Calibration::AnnounceRun(const std::string& event, const std::string& reason) {
    // Without a sequencer (measured data, the rig's own procedure) the launcher owns the run and
    // announces it; it also ends a run it must abort (a source died).
    run_event_t e;
    e.utime = bus::WallClockUtime();
    if (run_id_.empty()) {
        char buf[32];
        std::time_t t = std::time(nullptr);
        std::strftime(buf, sizeof buf, "%Y%m%dT%H%M%SZ", std::gmtime(&t));
        run_id_ = std::string(buf) + "-" + process::HostName() + "-" + std::to_string(getpid());
    }
    e.run_id = run_id_;
    e.event = event;
    e.reason = reason;
    e.setpoint_index = event == "abort" ? setpoint_index_ : -1;
    e.setpoint_c = event == "abort" && setpoint_index_ >= 0 ? setpoint_c_ : NAN;
    e.num_sensors = 0;
    e.software_version = kSoftwareVersion;
    e.config_json = ConfigJson();
    e.command_line = o_.command_line;
    e.host = process::HostName();
    bus_.Publish(std::string(channels::kRunEvent), e);
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
    // The fitter's final report follows each final set (and says "none" when there is no set);
    // the closed loop's comes after it.
    for (const auto& s : sensors) {
        if (!final_reports_.count(s)) return false;
        if (ClosedLoop() && !loop_reports_.count(s)) return false;
    }
    return true;
}

bool Calibration::ClosedLoop() const {
    if (IsRamp() || o_.profile == "seed3") return false;
    // The last word of the fitter's own arguments (--fitter-arg=--closed-loop=false) wins.
    bool on = true;
    for (size_t i = 0; i < o_.fitter_args.size(); ++i) {
        const std::string& a = o_.fitter_args[i];
        if (a.rfind("--closed-loop=", 0) == 0) on = a.substr(14) != "false" && a.substr(14) != "0";
        if (a == "--closed-loop" && i + 1 < o_.fitter_args.size())
            on = o_.fitter_args[i + 1] != "false" && o_.fitter_args[i + 1] != "0";
    }
    return on;
}

FinalVerdict Calibration::Verdict() const {
    return FinalVerdict{Sensors(), coeffs_, final_coeffs_, final_reports_};
}

bool Calibration::WaitsForCoeffs() const {
    // The producers' host has nothing to do with the coefficients once its source is done.
    return role_ != Role::kProducers && run_outcome_.rfind("stop", 0) == 0;
}

int Calibration::Run() {
    std::cout << "gyrocal calibrate: role " << RoleName(role_) << ", logs in " << o_.log_dir
              << ", database " << o_.db << ", LCM " << url_ << "\n";
    const auto named = sequencer::NamedProfile(o_.profile);
    const int setpoints = static_cast<int>(
        o_.setpoints_c.empty() ? (named ? named->setpoints_c.size() : 0) : o_.setpoints_c.size());
    const bool sequenced = source_kind_ == Source::kSim && o_.procedure == "sequencer";
    progress_ = std::make_unique<Progress>(sequenced ? setpoints : 0, sequenced ? 2 : 0);
    if (!StartConsumers()) return Finish(1);
    if (Runs("gyrocal-sim-rig") && !StartProducers()) return Finish(1);
    return Watch();
}

bool Calibration::DetectEnd() {
    if (sequencer_) {
        const auto s = sequencer_->proc->Poll();
        return s && s->exited && (s->code == 0 || s->code == 3);  // it ended the run
    }
    if (source_) {
        const auto s = source_->proc->Poll();
        if (!s) return false;
        if (!run_ended_) {
            // Let the processors drain what the source published before closing the run.
            for (int i = 0; i < 20; ++i) bus_.Handle(50ms);
            if (s->exited && s->code == 0) {
                AnnounceRun("stop", "end of data");
            } else {
                // The source's own words, printed and stored with the run (child_errors.hpp).
                const std::string reason =
                    WithCause(o_.source + " source " + s->Describe(), CauseOf(*source_));
                std::cerr << "\ngyrocal calibrate: aborting the run: " << reason << "\n";
                run_outcome_ = "abort: " + reason;
                AnnounceRun("abort", reason);
            }
        }
        return true;
    }
    return run_ended_;  // a host without the source: the run's own end event
}

int Calibration::Watch() {
    while (true) {
        bus_.Handle(50ms);
        ShowProgress(false);
        RecoverDue();
        if (process::StopRequested()) {
            std::cout << "\ngyrocal calibrate: interrupted; stopping the run\n";
            if (sequencer_) sequencer_->proc->Signal(SIGTERM);  // it records the abort
            if (!sequencer_ && source_) AnnounceRun("abort", "operator stop (signal)");
            for (int i = 0; i < 40 && sequencer_ && !sequencer_->proc->Poll(); ++i)
                bus_.Handle(50ms);
            run_outcome_ = "abort: operator stop";
            return Finish(3);
        }
        if (auto code = Supervise()) return Finish(*code);
        if (!ended_at_) {
            if (DetectEnd()) ended_at_ = Clock::now();
        } else {
            // Give the end event a moment to arrive (a source's own end is seen before its event).
            if (!run_ended_ && SecondsSince(*ended_at_) < 2) continue;
            if (!WaitsForCoeffs() || HaveFinalCoeffs()) break;
            // The closed loop after the plateau sets, and the ramp at its stop, fit each unit on
            // every still bin of the run (seconds per unit on a busy machine, more the longer
            // the run: 6 s at 17 h of data): the wait grows with the units.
            const double wait_s =
                o_.final_coeffs_wait_s +
                (ClosedLoop() || IsRamp() ? 60.0 * std::max<size_t>(1, Sensors().size()) : 0.0);
            if (SecondsSince(*ended_at_) > wait_s) {
                std::cerr << "\ngyrocal calibrate: no final coefficient set within " << wait_s
                          << " s from every sensor\n";
                break;
            }
        }
        if (o_.wall_timeout_s > 0 && SecondsSince(start_) > o_.wall_timeout_s) {
            std::cerr << "\ngyrocal calibrate: wall-clock limit of " << o_.wall_timeout_s
                      << " s reached\n";
            if (sequencer_) sequencer_->proc->Signal(SIGTERM);
            for (int i = 0; i < 40 && sequencer_ && !sequencer_->proc->Poll(); ++i)
                bus_.Handle(50ms);
            run_outcome_ = "abort: wall-clock limit";
            return Finish(3);
        }
    }
    ShowProgress(true);
    std::cout << "\n";
    int code = 0;
    if (sequencer_ && !(sequencer_->proc->Poll()->exited && sequencer_->proc->Poll()->code == 0))
        code = 3;
    if (run_outcome_.rfind("stop", 0) != 0) code = 3;
    if (WaitsForCoeffs() && !HaveFinalCoeffs()) code = 3;
    if (WaitsForCoeffs() && !Verdict().AllComplete()) code = 3;
    return Finish(code);
}

int Calibration::Finish(int code) {
    acker_.Leave();  // no source waits for this launcher while it stops the graph
    StopAll();
    std::cout << "\nrun " << (run_id_.empty() ? "(none)" : run_id_) << ": "
              << (run_outcome_.empty() ? "not finished" : run_outcome_) << "\n";
    if (progress_)
        std::cout << "losses seen on the bus (sequence gaps + decode errors + queue drops + "
                     "handler errors): "
                  << progress_->drops() << "\n";
    if (!coeffs_.empty()) {
        std::cout << "\n" << FormatCoeffTable(coeffs_, Verdict().Labels());
        if (ClosedLoop() && !plateau_sets_.empty())
            std::cout << "\nplateau sets (plateau means only; stored beside the final sets, source "
                      << model::kFitterSource << ")\n"
                      << FormatCoeffTable(plateau_sets_);
        if (!loop_analyses_.empty() || !loop_reports_.empty())
            std::cout << "\n" << ClosedLoopLines();
        std::ifstream truth(o_.truth_out);
        if (truth && source_kind_ == Source::kSim) {
            try {
                std::cout << "\n" << FormatTruthComparison(coeffs_, nlohmann::json::parse(truth));
            } catch (const std::exception& e) {
                std::cerr << "gyrocal calibrate: cannot compare with the truth in " << o_.truth_out
                          << ": " << e.what() << "\n";
            }
        }
    }
    std::cout << "\ndatabase: " << o_.db << "   logs: " << o_.log_dir << "\n";
    if (stop_seen_ && WaitsForCoeffs()) std::cerr << Verdict().Explain();
    // The acceptance step reads the database: on the host that holds it.
    if (services_.after_run && !run_id_.empty() && Runs("gyrocal-recorder"))
        code = services_.after_run(o_, run_id_, code);
    return code;
}

int RunCalibration(const CalibrateOptions& options, const StoreServices& services) {
    process::InstallStopHandlers();
    CalibrateOptions o = options;
    if (o.command_line.empty()) {
        // The command line as the kernel has it (NUL-separated), recorded with the run.
        std::ifstream f("/proc/self/cmdline");
        for (std::string arg; std::getline(f, arg, '\0');)
            o.command_line += (o.command_line.empty() ? "" : " ") + arg;
    }
    // Measured input that cannot be replayed is refused before any process starts (no run).
    if (RoleRuns(*ParseRole(o.role), "gyrocal-sim-rig")) {
        if (const std::string problem = MeasuredInputProblem(o); !problem.empty()) {
            process::PrintError("gyrocal calibrate", problem);
            std::cerr << "gyrocal calibrate: no run was started (the input was checked before "
                         "the process graph)\n";
            return 2;
        }
    }
    try {
        o.lcm_url = EffectiveLcmUrl(o);
        Calibration c(o, services);
        return c.Run();
    } catch (const bus::BusError& e) {
        std::cerr << "gyrocal calibrate: " << e.what() << "\n";
        return 1;
    } catch (const std::exception& e) {
        std::cerr << "gyrocal calibrate: " << e.what() << "\n";
        return 1;
    }
}

}  // namespace gyrocal::supervisor
