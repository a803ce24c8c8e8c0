// gyrocal-compensator: GYRO_* and COEFFS_* in; RATE_<id> and STATUS out.
// Threads: one. Bus::Handle dispatches on this thread, so a coefficient set received between two
// samples is complete before the next sample is computed (the atomic swap). All numbers are
// decided by SensorCompensator (compensate.hpp); handlers guard, call it and publish.
#include <CLI/CLI.hpp>
#include <cmath>
#include <map>
#include <set>

#include "bus/bus.hpp"
#include "bus/channels.hpp"
#include "bus/process_main.hpp"
#include "bus/status.hpp"
#include "compensator/compensate.hpp"
#include "gyrocal/gyro_sample_t.hpp"
#include "gyrocal/rate_t.hpp"

namespace gyrocal {
namespace {

constexpr const char* kProcess = "gyrocal-compensator";

// Why the process extrapolates outside a model's valid range by default (PX4 clips): measured by
// tests/bench/procedure (gyrocal_bench_procedure, 6 seeds x 4 units, held-out profile
// 25 -> -40 -> 85 -> 25 degC), a calibration over -10..60 degC applied CLIPPED errs up to
// 7.1 deg/s outside its range and drifts ~1450 deg/h over the record: a clipped offset stops
// following the unit's curvature while the unit does not stop. EXTRAPOLATING the same fits
// leaves 0.036 deg/s RMS (seed 3-point method; max 0.21 deg/s outside the range), and still
// 0.195 deg/s RMS with an undeclared cubic effect in the rig (temp_cubic=2e-8). Every such sample
// stays flagged (rate_t.range_flag = 2, extrapolated), so each consumer knows it was outside the
// calibrated range; --out-of-range clip remains for models that must not be trusted outside it.
constexpr model::RangePolicy kDefaultRangePolicy = model::RangePolicy::kExtrapolate;

struct CompensatorNodeOptions {
    std::string lcm_url;  // "" = $GYROCAL_LCM_URL or the default
    compensate::CompensatorOptions core;
    std::vector<std::string> sensors;  // empty = every sensor
    static CompensatorNodeOptions Defaults() {
        CompensatorNodeOptions o;
        o.core.range_policy = kDefaultRangePolicy;
        return o;
    }
};

class CompensatorNode {
public:
    explicit CompensatorNode(const CompensatorNodeOptions& o)
        : options_(o),
          bus_(BusOptions{o.lcm_url}),
          status_(bus_, kProcess),
          only_(o.sensors.begin(), o.sensors.end()) {
        bus_.Subscribe<gyro_sample_t>(
            channels::AllSensors(channels::kGyroPrefix),
            [this](const gyro_sample_t& m, const std::string& ch) { OnGyro(m, ch); });
        bus_.Subscribe<coeff_set_t>(
            channels::AllSensors(channels::kCoeffsPrefix),
            [this](const coeff_set_t& m, const std::string& ch) { OnCoeffs(m, ch); });
        status_.set_state("waiting for coefficients");
        UpdateStatus();
    }

    // The loop's done() hook refreshes the STATUS counters between dispatches (never stops it).
    void Run() {
        RunLoop(bus_, status_, [this] {
            UpdateStatus();
            return false;
        });
    }

private:
    void OnCoeffs(const coeff_set_t& m, const std::string& channel) {
        try {
            const std::string id = channels::SensorOf(channels::kCoeffsPrefix, channel).value();
            if (!Wanted(id)) return;
            if (m.sensor_id != id) {
                Rejected("wrong_sensor", channel + " carries sensor_id '" + m.sensor_id + "'");
                return;
            }
            model::CoeffSet set;
            try {
                set = model::FromMsg(m);
            } catch (const model::ModelError& e) {
                Rejected("bad_coeff_set", channel + " set " + std::to_string(m.coeff_set_id) +
                                              ": " + e.what() +
                                              " (the previous set stays in force)");
                return;
            }
            const compensate::SetResult r = Comp(id).SetCoefficients(set);
            if (r.outcome == compensate::SetOutcome::kRejected) {
                Rejected("bad_coeff_set", channel + " set " + std::to_string(m.coeff_set_id) +
                                              ": " + r.detail +
                                              " (the previous set stays in force)");
            } else if (r.outcome == compensate::SetOutcome::kApplied) {
                ++sets_applied_;
                status_.SetExtra(id + ".coeff_set_id", static_cast<double>(m.coeff_set_id));
                status_.set_state("compensating");
            }
            UpdateStatus();
        } catch (const std::exception& e) {
            status_.Reject("internal_error", e.what());
        }
    }

    void OnGyro(const gyro_sample_t& m, const std::string& channel) {
        try {
            const std::string id = channels::SensorOf(channels::kGyroPrefix, channel).value();
            if (!Wanted(id)) return;
            if (m.sensor_id != id) {
                status_.Reject("wrong_sensor",
                               channel + " carries sensor_id '" + m.sensor_id + "'");
                return;
            }
            const compensate::ApplyResult r =
                Comp(id).Apply({m.utime, m.seq, m.gyro_v, m.temp_c, m.supply_v});
            switch (r.status) {
                case compensate::ApplyStatus::kOk:
                    break;
                case compensate::ApplyStatus::kNoCoefficients:
                    ++uncompensated_;
                    return;
                default:
                    status_.Reject(compensate::ToString(r.status),
                                   channel + " seq " + std::to_string(m.seq) + ": " + r.detail);
                    return;
            }
            rate_t out{};
            out.utime = m.utime;
            out.sensor_id = id;
            out.seq = m.seq;
            out.rate_dps = r.out.rate_dps;
            out.angle_deg = r.out.angle_deg;
            out.temp_c = m.temp_c;
            out.coeff_set_id = r.out.coeff_set_id;
            out.range_flag = static_cast<int8_t>(r.out.range);
            if (r.out.range != model::RangeFlag::kInRange) ++out_of_range_;
            bus_.Publish(channels::Rate(id), out);
            ++compensated_;
        } catch (const std::exception& e) {
            status_.Reject("internal_error", e.what());
        }
    }

    bool Wanted(const std::string& id) const { return only_.empty() || only_.count(id) > 0; }

    compensate::SensorCompensator& Comp(const std::string& id) {
        auto it = comps_.find(id);
        if (it == comps_.end())
            it = comps_.emplace(id, compensate::SensorCompensator(options_.core)).first;
        return it->second;
    }

    void Rejected(const std::string& key, const std::string& detail) {
        ++sets_rejected_;
        status_.Reject(key, detail);
        UpdateStatus();
        status_.PublishNow();  // a refused calibration should be visible at once
    }

    void UpdateStatus() {
        status_.SetExtra("uncompensated", static_cast<double>(uncompensated_));
        status_.SetExtra("compensated", static_cast<double>(compensated_));
        status_.SetExtra("out_of_range", static_cast<double>(out_of_range_));
        status_.SetExtra("coeff_sets_applied", static_cast<double>(sets_applied_));
        status_.SetExtra("coeff_sets_rejected", static_cast<double>(sets_rejected_));
    }

    CompensatorNodeOptions options_;
    Bus bus_;
    StatusReporter status_;
    std::set<std::string> only_;
    std::map<std::string, compensate::SensorCompensator> comps_;
    int64_t uncompensated_ = 0, compensated_ = 0, out_of_range_ = 0, sets_applied_ = 0,
            sets_rejected_ = 0;
};

}  // namespace
}  // namespace gyrocal

int main(int argc, char** argv) {
    using gyrocal::CompensatorNodeOptions;
    CompensatorNodeOptions o = CompensatorNodeOptions::Defaults();
    std::string policy = gyrocal::model::ToString(o.core.range_policy);
    CLI::App app{
        "gyrocal-compensator: applies the newest COEFFS_<id> to every GYRO_<id> sample and "
        "publishes "
        "RATE_<id> (rate_dps, integrated angle_deg, range_flag).",
        "gyrocal-compensator"};
    app.add_option(
        "--lcm-url", o.lcm_url,
        "LCM URL (default: $GYROCAL_LCM_URL or " + std::string(gyrocal::kDefaultLcmUrl) + ")");
    app.add_option(
           "--out-of-range", policy,
           "outside a model's valid temperature range: extrapolate (continue the fitted "
           "polynomial; default) or clip (evaluate at the nearest bound). Either way "
           "rate_t.range_flag marks the sample (1 clipped, 2 extrapolated). Why extrapolate: "
           "on the benchmark (gyrocal_bench_procedure, held-out -40..85 degC), a -10..60 degC "
           "calibration clipped erred up to 7.1 deg/s and drifted ~1450 deg/h; extrapolated, "
           "0.036 deg/s RMS (0.195 deg/s RMS even with an undeclared cubic effect)")
        ->capture_default_str();
    app.add_option("--sensor", o.sensors,
                   "compensate only these sensor ids (repeatable); default: all");
    app.add_option("--temp-rate-window-s", o.core.temp_rate_window_s,
                   "window of the dT/dt slope used by dTdt/heating terms [s]")
        ->capture_default_str();
    app.footer(gyrocal::kNodeExitCodes);
    const auto validate = [&]() -> std::string {
        const auto p = gyrocal::model::ParseRangePolicy(policy);
        if (!p) return "--out-of-range '" + policy + "' is not valid: use clip or extrapolate";
        o.core.range_policy = *p;
        if (!(o.core.temp_rate_window_s > 0.0) || !std::isfinite(o.core.temp_rate_window_s))
            return "--temp-rate-window-s must be a finite number > 0";
        return gyrocal::channels::SensorIdsProblem(o.sensors, "--sensor");
    };
    if (auto exit_code = gyrocal::ParseCommandLine(app, argc, argv, gyrocal::kProcess, validate))
        return *exit_code;
    return gyrocal::RunUntilStopped(gyrocal::kProcess, [&] { gyrocal::CompensatorNode(o).Run(); });
}
