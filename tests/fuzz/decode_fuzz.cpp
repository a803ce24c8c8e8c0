// Fuzz one LCM message type through the decode every receiver runs on bytes from the network
// (gyrocal::DecodeMessage: Bus::Subscribe and the recorder). Built once per type
// (GYROCAL_FUZZ_TYPE, GYROCAL_FUZZ_HEADER).
// Contract: no crash and no exception; nothing allocated beyond what the payload's size
// justifies (run.sh sets libFuzzer's -malloc_limit_mb); a payload that decodes is at least as
// long as the message's encoded size, and the message re-encodes into bytes that decode again
// and encode to the same bytes.
#include <climits>
#include <cstdint>
#include <cstring>
#include <vector>

#include GYROCAL_FUZZ_HEADER
#include "lcmtypes/bus/decode.hpp"
#include "tests/fuzz/fuzz_check.hpp"

namespace {

using Msg = gyrocal::GYROCAL_FUZZ_TYPE;

std::vector<uint8_t> Encode(const Msg& m, int* written) {
    std::vector<uint8_t> buf(static_cast<size_t>(m.getEncodedSize()));
    *written = m.encode(buf.data(), 0, static_cast<int>(buf.size()));
    return buf;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size > static_cast<size_t>(INT_MAX)) return 0;
    Msg msg{};
    if (!gyrocal::bus::DecodeMessage(msg, data, static_cast<int>(size))) return 0;
    FUZZ_CHECK(msg.getEncodedSize() <= static_cast<int>(size),
               "decoded message is larger than its payload");
    int n1 = 0;
    const std::vector<uint8_t> b1 = Encode(msg, &n1);
    FUZZ_CHECK(n1 > 0, "a decoded message does not encode");
    Msg again{};
    FUZZ_CHECK(gyrocal::bus::DecodeMessage(again, b1.data(), static_cast<int>(b1.size())),
               "a re-encoded message does not decode");
    int n2 = 0;
    const std::vector<uint8_t> b2 = Encode(again, &n2);
    FUZZ_CHECK(n1 == n2 && std::memcmp(b1.data(), b2.data(), static_cast<size_t>(n1)) == 0,
               "decode(encode(m)) encodes to other bytes than m");
    return 0;
}
