#include <cmath>

#include "gyrocal/analysis_t.hpp"
#include "gyrocal/chamber_state_t.hpp"
#include "gyrocal/encoder_sample_t.hpp"
#include "gyrocal/gyro_sample_t.hpp"
#include "gyrocal/power_state_t.hpp"
#include "lcmtypes/channels/channels.hpp"
#include "processors/fitter/analysis_message.hpp"
#include "processors/fitter/node/fitter_node.hpp"

namespace gyrocal::fitter::node {

StillFitChannel::StillFitChannel(bus::Bus& bus, process::StatusReporter& status,
                                 fitter::RampFitter& fitter)
    : bus_(bus),
      status_(status),
      fitter_(fitter),
      worker_([&fitter](const fitter::FitJob& j) { return fitter.Run(j); }) {
    bus_.Subscribe<gyro_sample_t>(
        channels::AllSensors(channels::kGyroPrefix),
        [this](const gyro_sample_t& m, const std::string& ch) {
            status_.Guarded([&] {
                const auto id = channels::SensorOf(channels::kGyroPrefix, ch);
                // Guard: a sample the fit cannot use is counted, not kept.
                if (!id || !std::isfinite(m.gyro_v) || !std::isfinite(m.temp_c))
                    return status_.Reject("bad_sample", ch + ": non-finite gyro_v or temp_c");
                fitter_.AddGyro(*id, motion::GyroSampleOf(m));
                if (m.utime > now_utime_) {
                    now_utime_ = m.utime;
                    Submit(fitter_.DueJobs(m.utime));
                }
            });
        });
    bus_.Subscribe<encoder_sample_t>(
        std::string(channels::kEncoder), [this](const encoder_sample_t& m, const std::string&) {
            status_.Guarded([&] { fitter_.AddEncoder({m.utime, m.counts, m.counts_per_rev}); });
        });
    bus_.Subscribe<power_state_t>(
        channels::AllSensors(channels::kPowerPrefix),
        [this](const power_state_t& m, const std::string& ch) {
            status_.Guarded([&] {
                const auto id = channels::SensorOf(channels::kPowerPrefix, ch);
                if (!id || *id != m.sensor_id) return;
                fitter_.AddPower(*id, {m.utime, m.power_on_utime, m.source});
            });
        });
    bus_.Subscribe<chamber_state_t>(
        std::string(channels::kChamberState), [this](const chamber_state_t& m, const std::string&) {
            status_.Guarded([&] { fitter_.AddAir({m.utime, m.air_c}); });
        });
}

void StillFitChannel::Submit(std::vector<fitter::FitJob> jobs) {
    if (jobs.empty()) return;
    worker_.Submit(std::move(jobs));
    status_.SetExtra("still_fits_outstanding", static_cast<double>(worker_.outstanding()));
    status_.SetExtra("still_fits_superseded", static_cast<double>(worker_.superseded()));
    status_.SetExtra("still_bins_memory_bytes", static_cast<double>(fitter_.MemoryBytes()));
}

size_t StillFitChannel::Publish() {
    const std::vector<fitter::RampFitResult> results = worker_.Take();
    for (fitter::RampFitResult r : results) {
        if (r.report.source.empty()) r.report.source = fitter_.options().source;
        // A set before its report and its analysis, so that a listener that has the report has
        // the set.
        if (r.set) {
            bus_.Publish(channels::Coeffs(r.sensor_id), *r.set);
            ++sets_published_;
        }
        bus_.Publish(channels::Fit(r.sensor_id), r.report);
        // The analysis of a final fit (one per unit and run: the store keeps each one it hears).
        if (r.report.is_final)
            if (const auto a =
                    fitter::AnalysisMessage(r, r.report.run_id, fitter_.options().source))
                bus_.Publish(channels::Analysis(r.sensor_id), *a);
        status_.SetExtra(r.sensor_id + "." + fitter_.options().source + ".fitted",
                         r.set ? 1.0 : 0.0);
        max_fit_s_ = std::max(max_fit_s_, r.fit_wall_s);
        status_.SetExtra("still_fit_last_s", r.fit_wall_s);
    }
    if (!results.empty()) {
        status_.SetExtra("still_fit_max_s", max_fit_s_);
        status_.SetExtra("still_fits_outstanding", static_cast<double>(worker_.outstanding()));
        status_.SetExtra("still_bins_memory_bytes", static_cast<double>(fitter_.MemoryBytes()));
        status_.SetExtra(fitter_.options().source + ".sets_published",
                         static_cast<double>(sets_published_));
    }
    return results.size();
}

RampFitterNode::RampFitterNode(const FitterOptions& o)
    : bus_(bus::BusOptions{o.lcm_url}), status_(bus_, "gyrocal-fitter"), fitter_(o.ramp) {
    channel_.emplace(bus_, status_, fitter_);
    bus_.Subscribe<sensitivity_point_t>(
        channels::AllSensors(channels::kSensitivityPrefix),
        [this](const sensitivity_point_t& m, const std::string& ch) {
            status_.Guarded([&] {
                const auto id = channels::SensorOf(channels::kSensitivityPrefix, ch);
                if (!id) return;
                fitter_.AddSensitivity(
                    *id, {m.rotation_id, m.utime, m.temp_c, m.direction, m.sensitivity_v_per_dps,
                          m.sensitivity_stderr_v_per_dps, m.accepted != 0});
            });
        });
    bus_.Subscribe<run_event_t>(
        std::string(channels::kRunEvent), [this](const run_event_t& m, const std::string&) {
            status_.Guarded([&] {
                if (m.event == "start") fitter_.StartRun(m.run_id);
                if ((m.event == "stop" || m.event == "abort") && m.run_id == fitter_.run_id())
                    channel_->Submit(fitter_.FinishJobs(m.utime));
            });
            if (m.event == "stop" || m.event == "start") status_.PublishNow();
        });
    status_.set_state("waiting (ramp mode)");
}

void RampFitterNode::Run() {
    process::RunLoop(bus_, status_, [this] {
        if (channel_->Publish() > 0) status_.set_state("fitted (ramp mode)");
        return false;
    });
}

void RampFitterNode::HandleFor(int timeout_ms) {
    bus_.Handle(std::chrono::milliseconds(timeout_ms));
    if (channel_->Publish() > 0) status_.set_state("fitted (ramp mode)");
}

}  // namespace gyrocal::fitter::node
