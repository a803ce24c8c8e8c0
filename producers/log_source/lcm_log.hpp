#pragma once
// An LCM log file (what lcm-logger writes) read event by event, in bounded memory. Pure: no bus,
// no clock. The format (LCM's eventlog): each event is a sync word 0xEDA1DA01, the event number
// (int64), the receive time [us] (int64), the channel's length (int32), the data's length
// (int32), the channel, the data; every integer big-endian.
#include <cstdint>
#include <istream>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace gyrocal::log_source {

inline constexpr uint32_t kSyncWord = 0xEDA1DA01;
// Limits that only a damaged file exceeds: a channel name of LCM's own maximum, and a message
// of LCM's largest (fragmented UDP carries up to 4 GB in theory; lcm-logger never wrote one
// over a few MB for this project's types).
inline constexpr int32_t kMaxChannelBytes = 256;
inline constexpr int32_t kMaxDataBytes = 64 << 20;

struct Event {
    int64_t event_number = 0;
    int64_t utime = 0;  // [us] when lcm-logger received it
    std::string channel;
    std::vector<uint8_t> data;
};

// What is wrong with the file, with the byte offset of the event where it was found.
class LogError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

class LogReader {
public:
    LogReader(std::istream& in, std::string file) : in_(in), file_(std::move(file)) {}
    // The next event; nullopt at the end of the file. Throws LogError for a bad sync word, an
    // impossible length or an event cut short (naming the file and the offset).
    std::optional<Event> Next();
    int64_t offset() const { return offset_; }  // [B] where the next event starts

private:
    std::istream& in_;
    std::string file_;
    int64_t offset_ = 0;
};

}  // namespace gyrocal::log_source
