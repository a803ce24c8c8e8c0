#include "tests/support/virtual_lab/virtual_lab.hpp"

#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>
#include <memory>
#include <optional>
#include <stdexcept>
#include <variant>

#include "processors/plateau/node/noise_message.hpp"
#include "processors/plateau/node/plateau_message.hpp"
#include "processors/rotation/node/rotation_message.hpp"
#include "processors/sequencer/coeff_uncertainty.hpp"

namespace gyrocal::virtual_lab {

LabConfig LabConfig::For(const std::string& profile, fit::Method method) {
    LabConfig c;
    const auto p = sequencer::NamedProfile(profile);
    if (!p) {
        std::string valid;
        for (const std::string& n : sequencer::ProfileNames())
            valid += (valid.empty() ? "" : ", ") + n;
        throw std::invalid_argument("virtual lab: profile '" + profile +
                                    "' is unknown; valid: " + valid);
    }
    c.procedure.profile = *p;
    c.fitter.fit.method = method;
    return c;
}

namespace {

// The process graph as one RigSink. Each member mirrors one process's state.
class Pipeline : public sim::RigSink {
public:
    Pipeline(const LabConfig& c, sim::Rig& rig, RunResult& out)
        : c_(c),
          rig_(rig),
          out_(out),
          procedure_(sequencer::MakeRunner(ProcedureOptionsFor(c, rig))),
          motion_(c.move, c.motion_guard_s, c.encoder_stale_s),
          rotation_moves_(c.move),
          fitter_(c.fitter) {
        if (c.procedure.profile.continuous) ramp_.emplace(c.ramp_fitter);
        if (!c.procedure.profile.continuous && c.closed_loop) {
            fitter::RampFitterOptions o = fitter::RampFitterOptions::ClosedLoop();
            o.analysis = c.ramp_fitter.analysis;
            loop_.emplace(o);
        }
        for (const std::string& id : rig.sensor_ids()) {
            sensors_.push_back(std::make_unique<Sensor>(id, c));
            sensors_.back()->detector.SetChamberSetpoint(std::numeric_limits<double>::quiet_NaN());
        }
    }

    bool done() const { return procedure_->done(); }
    const sequencer::Runner& procedure() const { return *procedure_; }

    void OnGyro(const sim::GyroReading& r, const sim::GyroTruth&) override {
        if (r.unit_index == 0) ++out_.samples_per_sensor;
        AdvanceTime(r.utime);
        Sensor& s = *sensors_[static_cast<size_t>(r.unit_index)];
        if (ramp_) ramp_->AddGyro(s.id, motion::GyroSampleOf(r));
        if (loop_) loop_->AddGyro(s.id, motion::GyroSampleOf(r));
        // gyrocal-plateau: queue until the table's motion around the sample is known.
        s.pending.push_back(plateau::SampleOf(r));
        s.newest_utime = r.utime;
        Drain(s);
        // gyrocal-rotation.
        s.estimator.AddSample(rotation::Sample{r.utime, r.seq, r.gyro_v, r.temp_c});
        Poll(s);
    }

    void OnEncoder(const sim::EncoderReading& r) override {
        const motion::EncoderReading e{r.utime, r.counts, r.counts_per_rev};
        if (ramp_) ramp_->AddEncoder({r.utime, r.counts, r.counts_per_rev});
        if (loop_) loop_->AddEncoder({r.utime, r.counts, r.counts_per_rev});
        // gyrocal-plateau's table motion, then its queued samples.
        motion_.Feed(e);
        int64_t oldest = std::numeric_limits<int64_t>::max();
        for (auto& s : sensors_) {
            Drain(*s);
            oldest =
                std::min(oldest, s->pending.empty() ? s->newest_utime : s->pending.front().utime);
        }
        motion_.Prune(oldest);
        // gyrocal-rotation's own move detector (every reading also to the slip check).
        for (auto& s : sensors_) s->estimator.AddEncoder(e);
        if (auto move = rotation_moves_.Feed(e)) {
            for (auto& s : sensors_) s->estimator.AddMove(*move);
        }
        for (auto& s : sensors_) Poll(*s);
    }

    void OnChamber(const sim::ChamberReading& r) override {
        for (auto& s : sensors_) s->detector.SetChamberSetpoint(r.setpoint_c);
        if (loop_) loop_->AddAir({r.utime, r.air_c});
        AdvanceTime(r.utime);
        if (!procedure_->done()) Execute(procedure_->OnChamber(r.utime, r.air_c));
    }

private:
    struct Sensor {
        Sensor(std::string sensor_id, const LabConfig& c)
            : id(std::move(sensor_id)),
              detector(c.plateau),
              noise(c.noise),
              estimator(c.rotation) {}
        std::string id;
        plateau::PlateauDetector detector;
        noise::NoiseTracker noise;
        std::deque<plateau::Sample> pending;
        int64_t newest_utime = 0;
        rotation::RotationEstimator estimator;
    };

    static sequencer::ProcedureOptions ProcedureOptionsFor(const LabConfig& c,
                                                           const sim::Rig& rig) {
        sequencer::ProcedureOptions p = c.procedure;
        if (p.sensor_ids.empty()) p.sensor_ids = rig.sensor_ids();
        return p;
    }

    void AdvanceTime(int64_t utime) {
        // The sequencer's guard: data time never runs backwards for the procedure.
        if (utime <= procedure_now_utime_) return;
        procedure_now_utime_ = utime;
        Execute(procedure_->OnTime(utime));
        if (ramp_ && !procedure_->done()) CollectRamp(ramp_->OnTime(utime));
    }

    void Drain(Sensor& s) {
        while (!s.pending.empty() && motion_.Decided(s.pending.front().utime, s.newest_utime)) {
            plateau::Sample ps = s.pending.front();
            s.pending.pop_front();
            ps.moving = motion_.Moving(ps.utime);
            s.noise.Add(ps, ps.moving);
            const plateau::Step step = s.detector.Feed(ps);
            if (step.plateau) {
                DeliverNoise(s);
                DeliverPlateau(s.id, *step.plateau);
            }
        }
    }

    void Poll(Sensor& s) {
        const rotation::MotionView view{rotation_moves_.watermark_utime(),
                                        rotation_moves_.current_start_utime()};
        for (const rotation::Point& p : s.estimator.Poll(view)) {
            out_.sensitivity_points.push_back(rotation::node::ToMessage(s.id, run_id_, p));
            const gyrocal::sensitivity_point_t& m = out_.sensitivity_points.back();
            if (!procedure_->done()) {
                if (ramp_)
                    ramp_->AddSensitivity(s.id, {m.rotation_id, m.utime, m.temp_c, m.direction,
                                                 m.sensitivity_v_per_dps,
                                                 m.sensitivity_stderr_v_per_dps, m.accepted != 0});
                if (loop_)
                    loop_->AddSensitivity(s.id, {m.rotation_id, m.utime, m.temp_c, m.direction,
                                                 m.sensitivity_v_per_dps,
                                                 m.sensitivity_stderr_v_per_dps, m.accepted != 0});
                Collect(fitter_.OnSensitivity(m, s.id));
                Execute(procedure_->OnSensitivity(s.id, m.utime));
            }
        }
    }

    void DeliverNoise(Sensor& s) {
        out_.noise[s.id] = plateau::node::ToNoiseMessage(s.id, run_id_, s.noise.Estimate());
        if (!procedure_->done()) Collect(fitter_.OnNoise(out_.noise[s.id], s.id));
    }

    void DeliverPlateau(const std::string& id, const plateau::Plateau& p) {
        out_.plateaus.push_back(plateau::node::ToMessage(id, p));
        const gyrocal::plateau_t& m = out_.plateaus.back();
        if (procedure_->done()) return;  // after the run's stop: a process would refuse it too
        if (loop_)
            loop_->AddPlateau(id, {m.plateau_id, m.start_utime, m.end_utime, m.temp_mean_c,
                                   m.temp_sem_c, m.gyro_mean_v, m.gyro_sem_v, m.n_samples});
        if (!ramp_) Collect(fitter_.OnPlateau(m, id));
        Execute(procedure_->OnPlateau(id, m.utime, m.setpoint_c));
    }

    void Collect(const fitter::CoreOutput& o) {
        for (const auto& r : o.rejections) out_.fitter_rejections.push_back(r);
        for (const auto& r : o.reports) out_.reports.push_back(r);
        for (const auto& set : o.publish) {
            out_.published.push_back(set);
            out_.final_sets[set.sensor_id] = model::FromMsg(set);
        }
    }

    // The ramp fitter's sets: published as the plateau fitter's are, and their uncertainty over
    // the planned range to the procedure (the sequencer's early stop).
    void CollectRamp(const std::vector<fitter::RampFitResult>& results) {
        const auto& wp = c_.procedure.profile.setpoints_c;
        const auto [lo, hi] = std::minmax_element(wp.begin(), wp.end());
        for (const auto& r : results) {
            out_.reports.push_back(r.report);
            if (!r.set) continue;
            out_.published.push_back(*r.set);
            const model::CoeffSet set = model::FromMsg(*r.set);
            out_.final_sets[set.sensor_id] = set;
            if (!procedure_->done())
                Execute(procedure_->OnCoefficients(set.sensor_id, set.utime,
                                                   sequencer::UncertaintyOver(set, *lo, *hi)));
        }
    }

    gyrocal::run_event_t RunEvent(const sequencer::RunEventOrder& r) const {
        gyrocal::run_event_t m;
        m.utime = rig_.now_utime();
        m.run_id = c_.run_id;
        m.event = r.event;
        m.reason = r.reason;
        m.setpoint_index = r.setpoint_index;
        m.setpoint_c = r.setpoint_c;
        m.sensor_ids = ProcedureOptionsFor(c_, rig_).sensor_ids;
        m.num_sensors = static_cast<int16_t>(m.sensor_ids.size());
        return m;
    }

    void Execute(const std::vector<sequencer::Order>& orders) {
        for (const sequencer::Order& order : orders) {
            if (const auto* ch = std::get_if<sequencer::ChamberOrder>(&order)) {
                const auto res =
                    rig_.ChamberCommand(++chamber_cmd_id_, ch->setpoint_c, ch->ramp_rate_c_per_min);
                if (!res.accepted) out_.notes.push_back("chamber refused: " + res.reason);
            } else if (const auto* t = std::get_if<sequencer::TurntableOrder>(&order)) {
                const auto res =
                    rig_.TurntableCommand(++table_cmd_id_, t->move_deg, t->rate_dps, t->accel_dps2);
                if (!res.accepted) out_.notes.push_back("turntable refused: " + res.reason);
            } else if (const auto* r = std::get_if<sequencer::RunEventOrder>(&order)) {
                OnRunEvent(*r);
            }
        }
    }

    void OnRunEvent(const sequencer::RunEventOrder& r) {
        const gyrocal::run_event_t msg = RunEvent(r);
        if (r.event == "start") {
            out_.start_utime = rig_.now_utime();
            run_id_ = c_.run_id;
            for (auto& s : sensors_) s->noise.Reset();
            for (auto& s : sensors_) s->detector.StartRun(run_id_);
            if (ramp_) ramp_->StartRun(run_id_);
            if (loop_) {
                loop_->StartRun(run_id_);
                // The rig announces its start as every unit's power-on (POWER_<id>).
                for (auto& s : sensors_)
                    loop_->AddPower(s->id, {rig_.now_utime(), c_.rig.start_utime, "rig"});
            }
        } else if (r.event == "setpoint") {
            for (auto& s : sensors_) s->detector.OnSetpointEvent(r.setpoint_c);
        } else if (r.event == "stop" || r.event == "abort") {
            out_.last_point_utime = rig_.now_utime();
            for (auto& s : sensors_)
                out_.noise[s->id] =
                    plateau::node::ToNoiseMessage(s->id, run_id_, s->noise.Estimate());
            run_id_.clear();
            for (auto& s : sensors_) s->detector.EndRun();
        }
        if (ramp_ && (r.event == "stop" || r.event == "abort"))
            CollectRamp(ramp_->Finish(rig_.now_utime()));
        else if (!ramp_)
            Collect(fitter_.OnRunEvent(msg));
        if (loop_ && (r.event == "stop" || r.event == "abort"))
            for (const fitter::FitJob& job : loop_->FinishJobs(rig_.now_utime())) {
                const fitter::RampFitResult res = loop_->Run(job);
                out_.closed_loop_bins[res.sensor_id] = job.bins;
                if (res.analysis) out_.closed_loop_results[res.sensor_id] = *res.analysis;
                if (res.set) out_.closed_loop_sets[res.sensor_id] = model::FromMsg(*res.set);
            }
        if (r.event == "stop" || r.event == "abort") rig_.StopAfterCurrentEvent();
    }

    const LabConfig& c_;
    sim::Rig& rig_;
    RunResult& out_;
    std::unique_ptr<sequencer::Runner> procedure_;
    motion::TableMotion motion_;           // gyrocal-plateau's
    motion::MoveDetector rotation_moves_;  // gyrocal-rotation's
    fitter::FitterCore fitter_;
    std::optional<fitter::RampFitter> ramp_;  // continuous profiles: the ramp fitter instead
    std::optional<fitter::RampFitter> loop_;  // plateau profiles: the closed loop beside it
    std::vector<std::unique_ptr<Sensor>> sensors_;
    std::string run_id_;
    int64_t procedure_now_utime_ = std::numeric_limits<int64_t>::min();
    int64_t chamber_cmd_id_ = 0, table_cmd_id_ = 0;
};

}  // namespace

RunResult Run(const LabConfig& config) {
    sim::Rig rig(config.rig);
    RunResult out;
    out.truths = rig.units();
    Pipeline pipeline(config, rig, out);
    const int64_t cap_utime = config.rig.start_utime + static_cast<int64_t>(config.max_sim_s * 1e6);
    rig.RunUntil(cap_utime, pipeline);  // returns at the run's stop, or at the cap
    out.end_utime = rig.now_utime();
    if (pipeline.done()) {
        out.outcome = pipeline.procedure().outcome();
        out.outcome_reason = pipeline.procedure().outcome_reason();
    } else {
        out.outcome = "cut";
        out.outcome_reason = "simulated-time cap max_sim_s reached";
        out.last_point_utime = out.end_utime;
    }
    for (const auto& n : pipeline.procedure().notes()) out.notes.push_back(n);
    return out;
}

}  // namespace gyrocal::virtual_lab
