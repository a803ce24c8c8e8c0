#pragma once
// Writes LCM log events as lcm-logger does (sync word, event number, utime, lengths, channel,
// data; big-endian), for the log source's tests.
#include <cstdint>
#include <ostream>
#include <string>
#include <vector>

namespace gyrocal::test {

inline void PutBig(std::ostream& out, uint64_t v, int bytes) {
    for (int i = bytes - 1; i >= 0; --i) out.put(static_cast<char>((v >> (8 * i)) & 0xff));
}

inline void WriteEvent(std::ostream& out, int64_t number, int64_t utime, const std::string& channel,
                       const std::vector<uint8_t>& data) {
    PutBig(out, 0xEDA1DA01u, 4);
    PutBig(out, static_cast<uint64_t>(number), 8);
    PutBig(out, static_cast<uint64_t>(utime), 8);
    PutBig(out, channel.size(), 4);
    PutBig(out, data.size(), 4);
    out.write(channel.data(), static_cast<std::streamsize>(channel.size()));
    out.write(reinterpret_cast<const char*>(data.data()),
              static_cast<std::streamsize>(data.size()));
}

}  // namespace gyrocal::test
