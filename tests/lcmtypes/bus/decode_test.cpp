// DecodeMessage: hostile payloads are refused before they size anything.
#include "lcmtypes/bus/decode.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "gyrocal/coeff_set_t.hpp"
#include "tests/lcmtypes/message_builders.hpp"

namespace gyrocal {
namespace {

// Found by the fuzz harnesses (tests/fuzz): an array length is checked against the payload before
// it sizes the array (an int32 num_plateaus of 2^31-1 made every COEFFS_* receiver zero 16 GB).
// Here 1e6 claimed elements in a 400-byte payload: nothing may be allocated for them.
TEST(Decode, AnArrayLengthThePayloadCannotHoldAllocatesNothing) {
    coeff_set_t m{};
    m.sensor_id = "S01";
    std::vector<uint8_t> buf = testing::EncodeMsg(m);
    const size_t at = buf.size() - 8;  // num_plateaus, then num_rotations (both 0 here)
    const uint32_t claimed = 1000000;
    for (int i = 0; i < 4; ++i) buf[at + i] = static_cast<uint8_t>(claimed >> (24 - 8 * i));
    coeff_set_t out{};
    EXPECT_FALSE(bus::DecodeMessage(out, buf.data(), static_cast<int>(buf.size())));
    EXPECT_EQ(out.plateau_ids.capacity(), 0u);
    // A negative length is refused the same way (it threw std::length_error before).
    buf[at] = 0xff;
    EXPECT_EQ(out.decode(buf.data(), 0, static_cast<int>(buf.size())), -1);
}

}  // namespace
}  // namespace gyrocal
