#include "processors/fitter/node/fitter_node.hpp"

#include <algorithm>
#include <string_view>

#include "lcmtypes/channels/channels.hpp"
#include "lcmtypes/process/process_main.hpp"

namespace gyrocal::fitter::node {

namespace {
constexpr const char* kProcess = "gyrocal-fitter";
}  // namespace

std::function<std::string()> AddFitterOptions(CLI::App& app, FitterOptions& o) {
    app.option_defaults()->always_capture_default();  // --help shows every option's default
    app.add_option(
        "--lcm-url", o.lcm_url,
        "LCM URL (default: $GYROCAL_LCM_URL or " + std::string(bus::kDefaultLcmUrl) + ")");
    app.add_option("--method", o.method,
                   "auto (3point with exactly 3 points, else wls), 3point, wls");
    app.add_option(
        "--min-temp-separation-c", o.core.fit.min_temp_separation_c,
        "[degC] temperatures closer than this add no polynomial degree (they stay data)");
    app.add_option(
        "--same-level-tolerance-c", o.core.fit.same_level_tolerance_c,
        "[degC] points closer than this in temperature are replicates of one temperature");
    app.add_option("--min-range-c", o.core.fit.min_range_c,
                   "[degC] a narrower range gets a line only (partial)");
    app.add_option("--max-degree", o.core.fit.max_degree,
                   "highest polynomial degree order selection may choose (1..3)");
    app.add_option("--fixed-degree", o.core.fit.fixed_degree,
                   "use this polynomial degree (1..3) for wls; 0 = choose on evidence (QAIC: AIC "
                   "with the overdispersion of the run's points, see processors/fit/fit.hpp)");
    app.add_option("--nominal-sensitivity-v-per-dps", o.core.nominal_sensitivity_v_per_dps,
                   "sensitivity published while a sensor has no accepted rotation [V/(deg/s)]");
    app.add_option(
        "--plateau-slow-noise-dps", o.core.plateau_slow_noise_dps,
        "[deg/s] slow noise in a plateau mean that its standard error cannot show, added "
        "in quadrature; 0..10 to give it, < 0 (default) = from the run's own Allan "
        "deviation (NOISE_<id>)");
    app.add_option("--outlier-alpha", o.core.outliers.family_alpha,
                   "chance per fit of excluding a good point (leave-one-out test), (0, 0.5)");
    app.add_flag("!--no-outlier-test", o.core.outliers.enabled, "keep every point");
    app.add_option("--pool-alpha", o.core.pool_alpha,
                   "false-alarm rate of the test that keeps disagreeing units out of the pooled "
                   "overdispersion, (0, 0.5)");
    app.add_option("--repeat-tolerance-c", o.core.repeat_tolerance_c,
                   "[degC] a plateau this close to an earlier one after others is a return "
                   "(repeatability)");
    app.add_option("--mode", o.mode,
                   "plateau (fit the plateaus) or ramp (fit every still window of a ramp run "
                   "with the analysis' term selection: processors/fitter/ramp_fitter.hpp)");
    app.add_option("--refit-interval-s", o.ramp.refit_interval_s,
                   "--mode ramp: [s] data time between fits during the run, 10..86400");
    app.add_option("--min-span-s", o.ramp.min_span_s,
                   "--mode ramp: [s] of a unit's data before its first fit, 0..86400");
    app.add_option("--max-bins-per-unit", o.ramp.max_bins_per_unit,
                   "--mode ramp and the closed loop: each unit's still bins held to this many "
                   "(beyond it neighbours merge into bins twice as long, so memory stops growing "
                   "with the run); 0 = no limit, else at least 64");
    app.add_option("--carry-cubic", o.ramp.carry_cubic,
                   "--mode ramp and the closed loop: the published set carries the cubic (dT^3) "
                   "when the verdict did not name it but it lowers the held-out error (the set is "
                   "for prediction; the verdict and the named effects are unchanged)");
    app.add_flag("--thermometer-lag-candidate", o.ramp.analysis.thermometer_lag_candidate,
                 "--mode ramp and the closed loop: the analysis also searches thermometer_lag "
                 "(dT*dTdt, a thermometer lagging the die; off by default: "
                 "processors/analysis/README.md)");
    app.add_option("--closed-loop", o.closed_loop,
                   "--mode plateau: at the stop, also fit each unit on every still sample with the "
                   "terms the data confirm and publish it as the run's final set (source "
                   "closed-loop) after the plateau set; false for the seed's 3-point method");
    app.footer(process::kNodeExitCodes);
    return [&o]() -> std::string {
        if (o.mode != "plateau" && o.mode != "ramp")
            return "--mode '" + o.mode + "' is not valid: use plateau or ramp";
        if (std::string p = o.ramp.Validate(); !p.empty()) return "--mode ramp: " + p;
        const auto method = fit::ParseMethod(o.method);
        if (!method) return "--method '" + o.method + "' is not valid: use auto, 3point or wls";
        o.core.fit.method = *method;
        return o.core.Validate();
    };
}

namespace {

// Subscribes `handle(m, id)` to every sensor's channel of `prefix`, `id` the channel's sensor id,
// guarded: what it throws is counted in STATUS.
template <class Msg, class Handle>
void SubscribePerSensor(bus::Bus& bus, process::StatusReporter& status, std::string_view prefix,
                        Handle handle) {
    bus.Subscribe<Msg>(channels::AllSensors(prefix), [&status, prefix, handle](
                                                         const Msg& m, const std::string& ch) {
        status.Guarded([&] { handle(m, channels::SensorOf(prefix, ch).value()); });
    });
}

fitter::RampFitterOptions ClosedLoopOptions(const FitterOptions& o) {
    fitter::RampFitterOptions c = fitter::RampFitterOptions::ClosedLoop();
    c.analysis = o.ramp.analysis;
    c.build = o.ramp.build;
    c.max_bins_per_unit = o.ramp.max_bins_per_unit;
    c.carry_cubic = o.ramp.carry_cubic;
    return c;
}

}  // namespace

FitterNode::FitterNode(const FitterOptions& o)
    : bus_(bus::BusOptions{o.lcm_url}), status_(bus_, kProcess), core_(o.core) {
    if (o.closed_loop) {
        loop_.emplace(ClosedLoopOptions(o));
        loop_channel_.emplace(bus_, status_, *loop_);
    }
    SubscribePerSensor<plateau_t>(
        bus_, status_, channels::kPlateauPrefix, [this](const plateau_t& m, const std::string& id) {
            if (loop_ && m.sensor_id == id)
                loop_->AddPlateau(id, {m.plateau_id, m.start_utime, m.end_utime, m.temp_mean_c,
                                       m.temp_sem_c, m.gyro_mean_v, m.gyro_sem_v, m.n_samples});
            Apply(core_.OnPlateau(m, id));
        });
    SubscribePerSensor<sensitivity_point_t>(
        bus_, status_, channels::kSensitivityPrefix,
        [this](const sensitivity_point_t& m, const std::string& id) {
            if (loop_ && m.sensor_id == id)
                loop_->AddSensitivity(
                    id, {m.rotation_id, m.utime, m.temp_c, m.direction, m.sensitivity_v_per_dps,
                         m.sensitivity_stderr_v_per_dps, m.accepted != 0});
            Apply(core_.OnSensitivity(m, id));
        });
    SubscribePerSensor<noise_t>(
        bus_, status_, channels::kNoisePrefix,
        [this](const noise_t& m, const std::string& id) { Apply(core_.OnNoise(m, id)); });
    bus_.Subscribe<run_event_t>(
        std::string(channels::kRunEvent), [this](const run_event_t& m, const std::string&) {
            status_.Guarded([&] {
                // The loop's run follows the core's (a new run's start).
                if (loop_ && m.event == "start" && m.run_id != loop_->run_id())
                    loop_->StartRun(m.run_id);
                Apply(core_.OnRunEvent(m));
            });
            if (m.event == "stop" || m.event == "start") status_.PublishNow();
        });
    status_.set_state("waiting");
}

void FitterNode::Run() {
    process::RunLoop(bus_, status_, [this] {
        if (loop_channel_) loop_channel_->Publish();
        return false;
    });
}

void FitterNode::HandleFor(int timeout_ms) {
    bus_.Handle(std::chrono::milliseconds(timeout_ms));
    if (loop_channel_) loop_channel_->Publish();
}

void FitterNode::Apply(const fitter::CoreOutput& out) {
    for (const fitter::Rejection& r : out.rejections) status_.Reject(r.key, r.detail);
    // A set before its report, so that a listener that has the report has the set.
    for (const coeff_set_t& set : out.publish) bus_.Publish(channels::Coeffs(set.sensor_id), set);
    for (const fit_report_t& r : out.reports) bus_.Publish(channels::Fit(r.sensor_id), r);
    // The run's final plateau sets (at its stop, or made again by a late point): the closed loop's
    // final sets follow them, fitted on every still sample, so that the newest set of a unit, the
    // one the compensator applies, is the closed loop's.
    if (loop_ && !core_.run_id().empty()) {
        // A run adopted from its points (no start heard) is the loop's too.
        if (loop_->run_id() != core_.run_id()) loop_->StartRun(core_.run_id());
        int64_t final_utime = -1;
        for (const fit_report_t& r : out.reports)
            if (r.is_final) final_utime = std::max(final_utime, r.utime);
        if (final_utime >= 0) {
            std::vector<fitter::FitJob> jobs = loop_->FinishJobs(final_utime);
            const auto summaries = core_.Summaries();
            for (fitter::FitJob& j : jobs) {
                const auto it = summaries.find(j.sensor_id);
                if (it == summaries.end() || !it->second.complete)
                    j.withhold =
                        "the plateau set is not complete (" +
                        (it == summaries.end() ? std::string("no plateau") : it->second.text) +
                        "): the temperatures do not support a temperature model";
            }
            loop_channel_->Submit(std::move(jobs));
        }
    }
    UpdateStatus();
}

void FitterNode::UpdateStatus() {
    std::string state;
    bool any_fitted = false;
    for (const auto& [id, s] : core_.Summaries()) {
        state += (state.empty() ? "" : "; ") + id + ": " + s.text;
        any_fitted = any_fitted || s.fitted;
        status_.SetExtra(id + ".plateaus", static_cast<double>(s.n_plateaus));
        status_.SetExtra(id + ".rotations", static_cast<double>(s.n_rotations));
        status_.SetExtra(id + ".fitted", s.fitted ? 1.0 : 0.0);
        status_.SetExtra(id + ".complete", s.complete ? 1.0 : 0.0);
        status_.SetExtra(id + ".excluded", static_cast<double>(s.excluded));
        status_.SetExtra(id + ".offset_chi2_per_dof", s.offset_chi2_per_dof);
        // c by which the plateaus' stated errors understate their scatter (fit.hpp); NaN
        // when there was no dof to estimate it.
        status_.SetExtra(id + ".offset_overdispersion", s.offset_overdispersion);
        status_.SetExtra(id + ".slow_noise_dps", s.slow_noise_dps);
    }
    status_.set_state((any_fitted ? "fitted: " : "waiting: ") +
                      (state.empty() ? "no points" : state));
    status_.SetExtra("coeff_sets_published", static_cast<double>(core_.published()));
    status_.SetExtra("rotations_not_accepted", static_cast<double>(core_.not_accepted_rotations()));
    status_.SetExtra("duplicates", static_cast<double>(core_.duplicates()));
}

}  // namespace gyrocal::fitter::node
