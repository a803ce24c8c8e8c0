#include "producers/log_source/lcm_log.hpp"

namespace gyrocal::log_source {

namespace {

// Reads `n` big-endian bytes; false at a clean end of file before the first byte.
bool ReadBig(std::istream& in, int n, uint64_t* out, bool* partial) {
    uint64_t v = 0;
    for (int i = 0; i < n; ++i) {
        const int c = in.get();
        if (c == std::char_traits<char>::eof()) {
            *partial = i > 0;
            return false;
        }
        v = (v << 8) | static_cast<uint8_t>(c);
    }
    *out = v;
    return true;
}

}  // namespace

std::optional<Event> LogReader::Next() {
    const int64_t at = offset_;
    auto fail = [&](const std::string& what) {
        return LogError(file_ + ": byte " + std::to_string(at) + ": " + what +
                        "; an LCM log (lcm-logger) holds events that start with the sync word "
                        "0xEDA1DA01");
    };
    uint64_t sync = 0, number = 0, utime = 0, channel_len = 0, data_len = 0;
    bool partial = false;
    if (!ReadBig(in_, 4, &sync, &partial)) {
        if (partial) throw fail("the file ends inside an event header");
        return std::nullopt;
    }
    if (sync != kSyncWord) throw fail("no sync word (not an LCM log, or damaged here)");
    if (!ReadBig(in_, 8, &number, &partial) || !ReadBig(in_, 8, &utime, &partial) ||
        !ReadBig(in_, 4, &channel_len, &partial) || !ReadBig(in_, 4, &data_len, &partial))
        throw fail("the file ends inside an event header");
    const auto channel_bytes = static_cast<int32_t>(channel_len);
    const auto data_bytes = static_cast<int32_t>(data_len);
    if (channel_bytes <= 0 || channel_bytes > kMaxChannelBytes)
        throw fail("channel length " + std::to_string(channel_bytes) + " outside 1.." +
                   std::to_string(kMaxChannelBytes));
    if (data_bytes < 0 || data_bytes > kMaxDataBytes)
        throw fail("data length " + std::to_string(data_bytes) + " outside 0.." +
                   std::to_string(kMaxDataBytes));
    Event e;
    e.event_number = static_cast<int64_t>(number);
    e.utime = static_cast<int64_t>(utime);
    e.channel.resize(static_cast<size_t>(channel_bytes));
    e.data.resize(static_cast<size_t>(data_bytes));
    in_.read(e.channel.data(), channel_bytes);
    in_.read(reinterpret_cast<char*>(e.data.data()), data_bytes);
    if (!in_) throw fail("the file ends inside an event (" + e.channel + ")");
    offset_ = at + 28 + channel_bytes + data_bytes;
    return e;
}

}  // namespace gyrocal::log_source
