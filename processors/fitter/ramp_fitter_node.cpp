#include <cmath>

#include "bus/channels.hpp"
#include "fitter_node.hpp"
#include "gyrocal/encoder_sample_t.hpp"
#include "gyrocal/gyro_sample_t.hpp"

namespace gyrocal {

RampFitterNode::RampFitterNode(const FitterOptions& o)
    : bus_(BusOptions{o.lcm_url}), status_(bus_, "gyrocal-fitter"), fitter_(o.ramp) {
    bus_.Subscribe<gyro_sample_t>(
        channels::AllSensors(channels::kGyroPrefix),
        [this](const gyro_sample_t& m, const std::string& ch) {
            status_.Guarded([&] {
                const auto id = channels::SensorOf(channels::kGyroPrefix, ch);
                // Guard: a sample the fit cannot use is counted, not kept.
                if (!id || !std::isfinite(m.gyro_v) || !std::isfinite(m.temp_c))
                    return status_.Reject("bad_sample", ch + ": non-finite gyro_v or temp_c");
                fitter_.AddGyro(*id, {m.utime, m.seq, m.temp_c, m.gyro_v, m.supply_v});
                if (m.utime > now_utime_) {
                    now_utime_ = m.utime;
                    Publish(fitter_.OnTime(m.utime));
                }
            });
        });
    bus_.Subscribe<encoder_sample_t>(std::string(channels::kEncoder),
                                     [this](const encoder_sample_t& m, const std::string&) {
                                         status_.Guarded([&] {
                                             fitter_.AddEncoder({m.utime, m.counts, m.counts_per_rev});
                                         });
                                     });
    bus_.Subscribe<sensitivity_point_t>(
        channels::AllSensors(channels::kSensitivityPrefix),
        [this](const sensitivity_point_t& m, const std::string& ch) {
            status_.Guarded([&] {
                const auto id = channels::SensorOf(channels::kSensitivityPrefix, ch);
                if (!id) return;
                fitter_.AddSensitivity(*id, {m.rotation_id, m.utime, m.temp_c, m.direction,
                                             m.sensitivity_v_per_dps,
                                             m.sensitivity_stderr_v_per_dps, m.accepted != 0});
            });
        });
    bus_.Subscribe<run_event_t>(std::string(channels::kRunEvent),
                                [this](const run_event_t& m, const std::string&) {
                                    status_.Guarded([&] {
                                        if (m.event == "start") fitter_.StartRun(m.run_id);
                                        if ((m.event == "stop" || m.event == "abort") &&
                                            m.run_id == fitter_.run_id())
                                            Publish(fitter_.Finish(m.utime));
                                    });
                                    if (m.event == "stop" || m.event == "start") status_.PublishNow();
                                });
    status_.set_state("waiting (ramp mode)");
}

void RampFitterNode::Run() { RunLoop(bus_, status_); }

void RampFitterNode::Publish(const std::vector<fitter::RampFitResult>& results) {
    for (const fitter::RampFitResult& r : results) {
        // A set before its report, so that a listener that has the report has the set.
        if (r.set) {
            bus_.Publish(channels::Coeffs(r.sensor_id), *r.set);
            ++sets_published_;
        }
        bus_.Publish(channels::Fit(r.sensor_id), r.report);
        status_.SetExtra(r.sensor_id + ".fitted", r.set ? 1.0 : 0.0);
    }
    if (!results.empty()) {
        status_.set_state("fitted (ramp mode)");
        status_.SetExtra("coeff_sets_published", static_cast<double>(sets_published_));
    }
}

}  // namespace gyrocal
