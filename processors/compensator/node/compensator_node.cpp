#include "processors/compensator/node/compensator_node.hpp"

#include "gyrocal/rate_t.hpp"
#include "lcmtypes/channels/channels.hpp"

namespace gyrocal::compensator::node {

namespace {
constexpr const char* kProcess = "gyrocal-compensator";
}

CompensatorNode::CompensatorNode(const CompensatorNodeOptions& o)
    : options_(o),
      bus_(bus::BusOptions{o.lcm_url}),
      status_(bus_, kProcess),
      only_(o.sensors.begin(), o.sensors.end()) {
    bus_.Subscribe<gyro_sample_t>(
        channels::AllSensors(channels::kGyroPrefix),
        [this](const gyro_sample_t& m, const std::string& ch) { OnGyro(m, ch); });
    bus_.Subscribe<power_state_t>(
        channels::AllSensors(channels::kPowerPrefix),
        [this](const power_state_t& m, const std::string& ch) { OnPower(m, ch); });
    bus_.Subscribe<coeff_set_t>(
        channels::AllSensors(channels::kCoeffsPrefix),
        [this](const coeff_set_t& m, const std::string& ch) { OnCoeffs(m, ch); });
    status_.set_state("waiting for coefficients");
    UpdateStatus();
}

void CompensatorNode::Run() {
    // The loop's done() hook refreshes the STATUS counters between dispatches (never stops it).
    process::RunLoop(bus_, status_, [this] {
        FlushRates();
        UpdateStatus();
        return false;
    });
}

bool CompensatorNode::HandleFor(int timeout_ms) {
    const bool handled = bus_.Handle(std::chrono::milliseconds(timeout_ms));
    FlushRates();
    UpdateStatus();
    return handled;
}

void CompensatorNode::FlushRates() {
    for (auto& [channel, rates] : pending_rates_) {
        if (rates.empty()) continue;
        bus_.PublishSamples(channel, std::move(rates));
        rates.clear();
    }
}

bool CompensatorNode::Accept(std::string_view prefix, const std::string& channel,
                             const std::string& msg_sensor, std::string* id) {
    *id = channels::SensorOf(prefix, channel).value();
    if (!only_.empty() && !only_.count(*id)) return false;
    if (msg_sensor == *id) return true;
    status_.Reject("wrong_sensor", channel + " carries sensor_id '" + msg_sensor + "'");
    return false;
}

void CompensatorNode::OnPower(const power_state_t& m, const std::string& channel) {
    status_.Guarded([&] {
        std::string id;
        if (!Accept(channels::kPowerPrefix, channel, m.sensor_id, &id)) return;
        Comp(id).PowerOn(m.power_on_utime);
    });
}

void CompensatorNode::OnCoeffs(const coeff_set_t& m, const std::string& channel) {
    status_.Guarded([&] {
        std::string id;
        if (!Accept(channels::kCoeffsPrefix, channel, m.sensor_id, &id)) return;
        const std::string which = channel + " set " + std::to_string(m.coeff_set_id) + ": ";
        compensator::SetResult r;
        try {
            r = Comp(id).SetCoefficients(model::FromMsg(m));
        } catch (const model::ModelError& e) {
            r = {compensator::SetOutcome::kRejected, e.what()};
        }
        if (r.outcome == compensator::SetOutcome::kRejected) {
            Rejected("bad_coeff_set", which + r.detail + " (the previous set stays in force)");
        } else if (r.outcome == compensator::SetOutcome::kApplied) {
            ++sets_applied_;
            status_.SetExtra(id + ".coeff_set_id", static_cast<double>(m.coeff_set_id));
            status_.set_state("compensating");
            if (!r.detail.empty()) status_.Reject("trackers_restarted", which + r.detail);
        }
        UpdateStatus();
    });
}

void CompensatorNode::OnGyro(const gyro_sample_t& m, const std::string& channel) {
    status_.Guarded([&] {
        std::string id;
        if (!Accept(channels::kGyroPrefix, channel, m.sensor_id, &id)) return;
        const compensator::ApplyResult r = Comp(id).Apply(compensator::SampleOf(m));
        if (r.status == compensator::ApplyStatus::kNoCoefficients) {
            ++uncompensated_;
            return;
        }
        if (r.status != compensator::ApplyStatus::kOk) {
            status_.Reject(compensator::ToString(r.status),
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
        pending_rates_[channels::Rate(id)].push_back(out);
        ++compensated_;
    });
}

compensator::SensorCompensator& CompensatorNode::Comp(const std::string& id) {
    auto it = comps_.find(id);
    if (it == comps_.end())
        it = comps_.emplace(id, compensator::SensorCompensator(options_.core)).first;
    return it->second;
}

void CompensatorNode::Rejected(const std::string& key, const std::string& detail) {
    ++sets_rejected_;
    status_.Reject(key, detail);
    UpdateStatus();
    status_.PublishNow();  // a refused calibration should be visible at once
}

void CompensatorNode::UpdateStatus() {
    int64_t assumed = 0;
    for (const auto& [id, c] : comps_) assumed += c.power_on_assumed() ? 1 : 0;
    status_.SetExtra("uncompensated", static_cast<double>(uncompensated_));
    status_.SetExtra("compensated", static_cast<double>(compensated_));
    status_.SetExtra("out_of_range", static_cast<double>(out_of_range_));
    status_.SetExtra("coeff_sets_applied", static_cast<double>(sets_applied_));
    status_.SetExtra("coeff_sets_rejected", static_cast<double>(sets_rejected_));
    // Sensors whose time since power-on counts from their first sample (no POWER_<id> seen).
    status_.SetExtra("power_on_assumed", static_cast<double>(assumed));
}

}  // namespace gyrocal::compensator::node
