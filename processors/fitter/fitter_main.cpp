// gyrocal-fitter: PLATEAU_*, SENSITIVITY_*, RUN_EVENT in; COEFFS_<id> and STATUS out.
// Threads: one. Bus::Handle dispatches on this thread; each handler guards, calls FitterCore
// (fitter_core.hpp, all the decisions) and publishes what it returns. SIGINT/SIGTERM end RunLoop.
#include <CLI/CLI.hpp>

#include "bus/bus.hpp"
#include "bus/channels.hpp"
#include "bus/process_main.hpp"
#include "bus/status.hpp"
#include "fitter/fitter_core.hpp"

namespace gyrocal {
namespace {

constexpr const char* kProcess = "gyrocal-fitter";

struct FitterOptions {
    std::string lcm_url;  // "" = $GYROCAL_LCM_URL or the default
    fitter::CoreOptions core;
    std::string method = "auto";
    static FitterOptions Defaults() { return {}; }
};

class FitterNode {
public:
    explicit FitterNode(const FitterOptions& o)
        : bus_(BusOptions{o.lcm_url}), status_(bus_, kProcess), core_(o.core) {
        bus_.Subscribe<plateau_t>(
            channels::AllSensors(channels::kPlateauPrefix),
            [this](const plateau_t& m, const std::string& ch) { OnPlateau(m, ch); });
        bus_.Subscribe<sensitivity_point_t>(
            channels::AllSensors(channels::kSensitivityPrefix),
            [this](const sensitivity_point_t& m, const std::string& ch) { OnSensitivity(m, ch); });
        bus_.Subscribe<run_event_t>(
            std::string(channels::kRunEvent),
            [this](const run_event_t& m, const std::string&) { OnRunEvent(m); });
        status_.set_state("waiting");
    }

    void Run() { RunLoop(bus_, status_); }

private:
    void OnPlateau(const plateau_t& m, const std::string& channel) {
        Guarded([&] {
            Apply(
                core_.OnPlateau(m, channels::SensorOf(channels::kPlateauPrefix, channel).value()));
        });
    }
    void OnSensitivity(const sensitivity_point_t& m, const std::string& channel) {
        Guarded([&] {
            Apply(core_.OnSensitivity(
                m, channels::SensorOf(channels::kSensitivityPrefix, channel).value()));
        });
    }
    void OnRunEvent(const run_event_t& m) {
        Guarded([&] { Apply(core_.OnRunEvent(m)); });
        if (m.event == "stop" || m.event == "start") status_.PublishNow();
    }

    // No exception escapes a handler: a failure is a counted refusal of that message.
    template <class F>
    void Guarded(F&& f) {
        try {
            f();
        } catch (const std::exception& e) {
            status_.Reject("internal_error", e.what());
        }
    }

    void Apply(const fitter::CoreOutput& out) {
        for (const fitter::Rejection& r : out.rejections) status_.Reject(r.key, r.detail);
        for (const coeff_set_t& set : out.publish)
            bus_.Publish(channels::Coeffs(set.sensor_id), set);
        UpdateStatus();
    }

    void UpdateStatus() {
        std::string state;
        bool any_fitted = false;
        for (const auto& [id, s] : core_.Summaries()) {
            state += (state.empty() ? "" : "; ") + id + ": " + s.text;
            any_fitted = any_fitted || s.fitted;
            status_.SetExtra(id + ".plateaus", static_cast<double>(s.n_plateaus));
            status_.SetExtra(id + ".rotations", static_cast<double>(s.n_rotations));
            status_.SetExtra(id + ".fitted", s.fitted ? 1.0 : 0.0);
            status_.SetExtra(id + ".offset_chi2_per_dof", s.offset_chi2_per_dof);
            // c by which the plateaus' stated errors understate their scatter (fit.hpp); NaN
            // when there was no dof to estimate it.
            status_.SetExtra(id + ".offset_overdispersion", s.offset_overdispersion);
        }
        status_.set_state((any_fitted ? "fitted: " : "waiting: ") +
                          (state.empty() ? "no points" : state));
        status_.SetExtra("coeff_sets_published", static_cast<double>(core_.published()));
        status_.SetExtra("rotations_not_accepted",
                         static_cast<double>(core_.not_accepted_rotations()));
        status_.SetExtra("duplicates", static_cast<double>(core_.duplicates()));
    }

    Bus bus_;
    StatusReporter status_;
    fitter::FitterCore core_;
};

}  // namespace
}  // namespace gyrocal

int main(int argc, char** argv) {
    using gyrocal::FitterOptions;
    FitterOptions o = FitterOptions::Defaults();
    CLI::App app{
        "gyrocal-fitter: fits offset and sensitivity models per sensor from PLATEAU_* and "
        "SENSITIVITY_* of the current run (RUN_EVENT) and publishes COEFFS_<sensor_id>.",
        "gyrocal-fitter"};
    app.add_option(
        "--lcm-url", o.lcm_url,
        "LCM URL (default: $GYROCAL_LCM_URL or " + std::string(gyrocal::kDefaultLcmUrl) + ")");
    app.add_option("--method", o.method,
                   "auto (3point with exactly 3 points, else wls), 3point, wls")
        ->capture_default_str();
    app.add_option("--min-temp-separation-c", o.core.fit.min_temp_separation_c,
                   "refuse a fit when two distinct temperatures are closer than this [degC]")
        ->capture_default_str();
    app.add_option(
           "--same-level-tolerance-c", o.core.fit.same_level_tolerance_c,
           "points closer than this in temperature are replicates of one temperature [degC]")
        ->capture_default_str();
    app.add_option("--min-range-c", o.core.fit.min_range_c,
                   "refuse a fit whose temperature range is narrower than this [degC]")
        ->capture_default_str();
    app.add_option("--max-degree", o.core.fit.max_degree,
                   "highest polynomial degree order selection may choose (1..3)")
        ->capture_default_str();
    app.add_option("--fixed-degree", o.core.fit.fixed_degree,
                   "use this polynomial degree (1..3) for wls; 0 = choose on evidence (QAIC: AIC "
                   "with the overdispersion of the run's points, see processors/fit/fit.hpp)")
        ->capture_default_str();
    app.add_option("--nominal-sensitivity-v-per-dps", o.core.nominal_sensitivity_v_per_dps,
                   "sensitivity published while a sensor has no accepted rotation [V/(deg/s)]")
        ->capture_default_str();
    app.add_option("--plateau-slow-noise-dps", o.core.plateau_slow_noise_dps,
                   "[deg/s] slow noise in a plateau mean that its standard error cannot show (from "
                   "the gyro's Allan deviation), added in quadrature; 0 = none, 0..10")
        ->capture_default_str();
    app.footer(gyrocal::kNodeExitCodes);
    const auto validate = [&]() -> std::string {
        const auto method = gyrocal::fit::ParseMethod(o.method);
        if (!method) return "--method '" + o.method + "' is not valid: use auto, 3point or wls";
        o.core.fit.method = *method;
        return o.core.Problem();
    };
    if (auto exit_code = gyrocal::ParseCommandLine(app, argc, argv, gyrocal::kProcess, validate))
        return *exit_code;
    return gyrocal::RunUntilStopped(gyrocal::kProcess, [&] { gyrocal::FitterNode(o).Run(); });
}
