#pragma once
// Turns stored rows back into the LCM messages they were recorded from, for `gyrocal-replay`.
// Socket-free: returns the channel and the encoded bytes; the main publishes them.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "store/db/rows.hpp"

namespace gyrocal::recorder {

struct EncodedMessage {
    std::string channel;
    std::vector<uint8_t> bytes;
};

// Gyro, encoder, chamber-state and run-event rows; nullopt for other row types. Throws
// std::invalid_argument when a stored sensor id cannot form a channel name.
std::optional<EncodedMessage> EncodeForReplay(const db::Row& row);

}  // namespace gyrocal::recorder
