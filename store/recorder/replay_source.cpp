#include "store/recorder/replay_source.hpp"

#include <stdexcept>

#include "lcmtypes/channels/channels.hpp"
#include "store/recorder/message_fields.hpp"

namespace gyrocal::recorder {
namespace {

// The message `row` was recorded from, encoded for `channel`.
template <class Msg, class R>
EncodedMessage Encode(std::string channel, const R& row) {
    Msg msg;
    CopyFields(msg, row);
    if constexpr (std::is_same_v<Msg, run_event_t>) {
        msg.num_sensors = static_cast<int16_t>(msg.sensor_ids.size());  // the length LCM encodes
    }
    EncodedMessage out{std::move(channel), {}};
    const int size = msg.getEncodedSize();
    out.bytes.resize(static_cast<size_t>(size));
    if (msg.encode(out.bytes.data(), 0, size) < 0) {
        throw std::invalid_argument("cannot encode " + std::string(Msg::getTypeName()));
    }
    return out;
}

}  // namespace

std::optional<EncodedMessage> EncodeForReplay(const db::Row& row) {
    if (const auto* g = std::get_if<db::GyroRow>(&row)) {
        return Encode<gyro_sample_t>(channels::Gyro(g->sensor_id), *g);
    }
    if (const auto* e = std::get_if<db::EncoderRow>(&row)) {
        return Encode<encoder_sample_t>(std::string(channels::kEncoder), *e);
    }
    if (const auto* p = std::get_if<db::PowerStateRow>(&row)) {
        return Encode<power_state_t>(channels::Power(p->sensor_id), *p);
    }
    if (const auto* c = std::get_if<db::ChamberStateRow>(&row)) {
        return Encode<chamber_state_t>(std::string(channels::kChamberState), *c);
    }
    if (const auto* r = std::get_if<db::RunEventRow>(&row)) {
        return Encode<run_event_t>(std::string(channels::kRunEvent), *r);
    }
    return std::nullopt;
}

}  // namespace gyrocal::recorder
