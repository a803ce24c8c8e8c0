#include "processors/sequencer/node/sequencer_node.hpp"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <iostream>
#include <nlohmann/json.hpp>

#include "gyrocal/chamber_cmd_t.hpp"
#include "gyrocal/chamber_state_t.hpp"
#include "gyrocal/coeff_set_t.hpp"
#include "gyrocal/gyro_sample_t.hpp"
#include "gyrocal/plateau_t.hpp"
#include "gyrocal/run_event_t.hpp"
#include "gyrocal/sensitivity_point_t.hpp"
#include "gyrocal/turntable_cmd_t.hpp"
#include "gyrocal/version.hpp"
#include "lcmtypes/channels/channels.hpp"
#include "lcmtypes/process/shutdown.hpp"
#include "processors/model/json.hpp"
#include "processors/sequencer/coeff_uncertainty.hpp"

namespace gyrocal::sequencer::node {
namespace {

std::string GeneratedRunId() {
    // A name, not a number any computation uses: wall time is fine here.
    std::time_t t = std::time(nullptr);
    char buf[32];
    std::strftime(buf, sizeof buf, "%Y%m%dT%H%M%SZ", std::gmtime(&t));
    return std::string(buf) + "-" + process::HostName() + "-" + std::to_string(getpid());
}

}  // namespace

SequencerOptions SequencerOptions::Defaults() {
    SequencerOptions o;
    o.procedure.profile = *NamedProfile(kDefaultProfile);
    return o;
}

SequencerNode::SequencerNode(SequencerOptions options)
    : options_(std::move(options)),
      bus_(bus::BusOptions{options_.lcm_url}),
      status_(bus_, "gyrocal-sequencer") {
    if (options_.run_id.empty()) options_.run_id = GeneratedRunId();
    nlohmann::json config = nlohmann::json::object();
    if (!options_.run_config_json.empty()) config = nlohmann::json::parse(options_.run_config_json);
    const ProcedureOptions& p = options_.procedure;
    nlohmann::json sequencer =
        GYROCAL_JSON_FIELDS(p, ramp_rate_c_per_min, plateau_timeout_s, moves_deg, rotation_rate_dps,
                            rotation_accel_dps2, rotation_timeout_s);
    sequencer["profile"] = p.profile.name;
    sequencer["setpoints_c"] = p.profile.setpoints_c;
    if (p.profile.continuous) {
        sequencer["continuous"] = true;
        sequencer.update(GYROCAL_JSON_FIELDS(p, turn_interval_s, dwell_s, target_offset_dps,
                                             target_sensitivity_pct));
    }
    config["sequencer"] = sequencer;
    config_json_ = config.dump();
    if (!p.sensor_ids.empty()) procedure_ = MakeRunner(p);

    bus_.Subscribe<chamber_state_t>(std::string(channels::kChamberState),
                                    [this](const chamber_state_t& s, const std::string&) {
                                        if (!s.fault.empty())
                                            status_.Reject("chamber fault", s.fault);
                                        OnAnyTime(s.utime);
                                        if (procedure_)
                                            Publish(procedure_->OnChamber(s.utime, s.air_c));
                                    });
    bus_.Subscribe<gyro_sample_t>(
        channels::AllSensors(channels::kGyroPrefix),
        [this](const gyro_sample_t& s, const std::string& channel) {
            if (!procedure_) {
                if (auto id = channels::SensorOf(channels::kGyroPrefix, channel))
                    discovered_.insert(*id);
            }
            OnAnyTime(s.utime);
        });
    bus_.Subscribe<plateau_t>(
        channels::AllSensors(channels::kPlateauPrefix),
        [this](const plateau_t& p, const std::string&) {
            if (procedure_) Publish(procedure_->OnPlateau(p.sensor_id, p.utime, p.setpoint_c));
        });
    bus_.Subscribe<sensitivity_point_t>(
        channels::AllSensors(channels::kSensitivityPrefix),
        [this](const sensitivity_point_t& s, const std::string&) {
            if (procedure_)
                Publish(
                    procedure_->OnSensitivity(s.sensor_id, s.utime, s.accepted, s.reject_reason));
        });
    if (p.profile.continuous) {
        bus_.Subscribe<coeff_set_t>(channels::AllSensors(channels::kCoeffsPrefix),
                                    [this](const coeff_set_t& m, const std::string&) {
                                        if (!procedure_ || m.run_id != options_.run_id) return;
                                        try {
                                            OnCoeffs(m.sensor_id, m.utime, model::FromMsg(m));
                                        } catch (const std::exception& e) {
                                            status_.Reject("bad coefficient set", e.what());
                                        }
                                    });
    }
    // A supervisor ends the run when a process it cannot restart died (gyrocal calibrate: the
    // rig); the sequencer then stops without ordering more. Its own events come back too (LCM
    // loops them back): by then the procedure is done and this changes nothing.
    bus_.Subscribe<run_event_t>(std::string(channels::kRunEvent),
                                [this](const run_event_t& e, const std::string&) {
                                    if (!procedure_ || e.run_id != options_.run_id) return;
                                    if (e.event == "abort" || e.event == "stop")
                                        procedure_->EndedElsewhere(e.event, e.reason);
                                });
}

void SequencerNode::MaybeStart(int64_t utime) {
    if (procedure_) return;
    if (first_utime_ < 0) first_utime_ = utime;
    if (static_cast<double>(utime - first_utime_) * 1e-6 < options_.discover_s ||
        discovered_.empty())
        return;
    ProcedureOptions p = options_.procedure;
    p.sensor_ids.assign(discovered_.begin(), discovered_.end());
    procedure_ = MakeRunner(p);
}

void SequencerNode::OnCoeffs(const std::string& sensor_id, int64_t utime,
                             const model::CoeffSet& set) {
    const auto& wp = options_.procedure.profile.setpoints_c;
    const auto [lo, hi] = std::minmax_element(wp.begin(), wp.end());
    Publish(procedure_->OnCoefficients(sensor_id, utime, UncertaintyOver(set, *lo, *hi)));
}

void SequencerNode::OnAnyTime(int64_t utime) {
    // Guard: data time never runs backwards for the procedure (late packets carry old stamps).
    if (utime <= now_utime_) return;
    now_utime_ = utime;
    MaybeStart(utime);
    if (procedure_) Publish(procedure_->OnTime(utime));
}

void SequencerNode::Publish(const std::vector<Order>& orders) {
    for (const Order& order : orders) std::visit([this](const auto& o) { PublishOrder(o); }, order);
    if (procedure_) {
        status_.set_state(PhaseName(procedure_->phase()));
        status_.SetExtra("setpoint_index", procedure_->setpoint_index());
        status_.SetExtra("pending_sensors",
                         static_cast<double>(procedure_->pending_sensors().size()));
    }
}

void SequencerNode::PublishOrder(const ChamberOrder& c) {
    auto m = Stamped<chamber_cmd_t>();
    m.cmd_id = ++chamber_cmd_id_;
    m.setpoint_c = c.setpoint_c;
    m.ramp_rate_c_per_min = c.ramp_rate_c_per_min;
    bus_.Publish(std::string(channels::kChamberCmd), m);
}

void SequencerNode::PublishOrder(const TurntableOrder& t) {
    auto m = Stamped<turntable_cmd_t>();
    m.cmd_id = ++turntable_cmd_id_;
    m.move_deg = t.move_deg;
    m.rate_dps = t.rate_dps;
    m.accel_dps2 = t.accel_dps2;
    bus_.Publish(std::string(channels::kTurntableCmd), m);
}

void SequencerNode::PublishOrder(const RunEventOrder& r) {
    auto m = Stamped<run_event_t>();
    m.event = r.event;
    m.reason = r.reason;
    m.setpoint_index = r.setpoint_index;
    m.setpoint_c = r.setpoint_c;
    m.sensor_ids = procedure_ ? std::vector<std::string>(discovered_.begin(), discovered_.end())
                              : std::vector<std::string>{};
    if (!options_.procedure.sensor_ids.empty()) m.sensor_ids = options_.procedure.sensor_ids;
    m.num_sensors = static_cast<int16_t>(m.sensor_ids.size());
    m.software_version = kSoftwareVersion;
    m.config_json = config_json_;
    m.command_line = options_.command_line;
    m.host = process::HostName();
    bus_.Publish(std::string(channels::kRunEvent), m);
    std::cout << "gyrocal-sequencer: " << r.event << " " << r.reason << std::endl;
}

int SequencerNode::Run() {
    status_.set_state("discovering sensors");
    process::RunLoop(bus_, status_, [this] { return procedure_ && procedure_->done(); });
    if (procedure_ && !procedure_->done()) Publish(procedure_->Abort("operator stop (signal)"));
    if (!procedure_) {
        std::cerr << "gyrocal-sequencer: stopped before any sensor was seen; no run was started\n";
        return 3;
    }
    for (const auto& note : procedure_->notes())
        std::cerr << "gyrocal-sequencer: note: " << note << "\n";
    status_.PublishNow();
    return procedure_->outcome() == "completed" ? 0 : 3;
}

}  // namespace gyrocal::sequencer::node
