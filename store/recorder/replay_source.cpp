#include "replay_source.hpp"

#include <stdexcept>

#include "bus/channels.hpp"
#include "gyrocal/chamber_state_t.hpp"
#include "gyrocal/encoder_sample_t.hpp"
#include "gyrocal/gyro_sample_t.hpp"
#include "gyrocal/power_state_t.hpp"
#include "gyrocal/run_event_t.hpp"

namespace gyrocal::record {
namespace {

template <class Msg>
EncodedMessage Encode(std::string channel, const Msg& msg) {
    EncodedMessage out{std::move(channel), {}};
    const int size = msg.getEncodedSize();
    out.bytes.resize(static_cast<size_t>(size));
    if (msg.encode(out.bytes.data(), 0, size) < 0) {
        throw std::invalid_argument("cannot encode " + std::string(Msg::getTypeName()));
    }
    return out;
}

}  // namespace

std::optional<EncodedMessage> EncodeForReplay(const store::Row& row) {
    if (const auto* g = std::get_if<store::GyroRow>(&row)) {
        gyro_sample_t m;
        m.utime = g->utime;
        m.sensor_id = g->sensor_id;
        m.seq = g->seq;
        m.gyro_v = g->gyro_v;
        m.temp_v = g->temp_v;
        m.temp_c = g->temp_c;
        m.supply_v = g->supply_v;
        m.has_adc = g->has_adc;
        m.gyro_counts = g->gyro_counts;
        m.temp_counts = g->temp_counts;
        m.supply_counts = g->supply_counts;
        return Encode(channels::Gyro(g->sensor_id), m);
    }
    if (const auto* e = std::get_if<store::EncoderRow>(&row)) {
        encoder_sample_t m;
        m.utime = e->utime;
        m.encoder_id = e->encoder_id;
        m.seq = e->seq;
        m.counts = e->counts;
        m.counts_per_rev = e->counts_per_rev;
        m.angle_deg = e->angle_deg;
        return Encode(std::string(channels::kEncoder), m);
    }
    if (const auto* p = std::get_if<store::PowerStateRow>(&row)) {
        power_state_t m;
        m.utime = p->utime;
        m.sensor_id = p->sensor_id;
        m.seq = p->seq;
        m.power_on_utime = p->power_on_utime;
        m.source = p->source;
        return Encode(channels::Power(p->sensor_id), m);
    }
    if (const auto* c = std::get_if<store::ChamberStateRow>(&row)) {
        chamber_state_t m;
        m.utime = c->utime;
        m.seq = c->seq;
        m.cmd_id = c->cmd_id;
        m.setpoint_c = c->setpoint_c;
        m.air_c = c->air_c;
        m.at_setpoint = c->at_setpoint;
        m.fault = c->fault;
        return Encode(std::string(channels::kChamberState), m);
    }
    if (const auto* r = std::get_if<store::RunEventRow>(&row)) {
        run_event_t m;
        m.utime = r->utime;
        m.run_id = r->run_id;
        m.event = r->event;
        m.reason = r->reason;
        m.setpoint_index = r->setpoint_index;
        m.setpoint_c = r->setpoint_c;
        m.sensor_ids = r->sensor_ids;
        m.num_sensors = static_cast<int16_t>(m.sensor_ids.size());
        m.software_version = r->software_version;
        m.config_json = r->config_json;
        m.command_line = r->command_line;
        m.host = r->host;
        return Encode(std::string(channels::kRunEvent), m);
    }
    return std::nullopt;
}

}  // namespace gyrocal::record
