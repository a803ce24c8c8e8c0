#pragma once
// The one decode of bytes received from the network, used by every receiver: Bus::Subscribe,
// the recorder's mapper and the fuzz harnesses (tests/fuzz), so what the fuzzers try is what
// the processes run.
//
// Bytes off the network are hostile until decoded: the generated decode checks every length
// against the payload before it sizes anything (lcmtypes/bound_decode.cmake), so a bad payload
// fails with -1 instead of allocating what its length fields claim. What can still throw (an
// allocation the payload's own size justifies, on a machine out of memory) is caught here:
// a receive handler must never throw through LCM's C stack.
#include <exception>

namespace gyrocal::bus {

// Decodes `size` bytes (8-byte type hash first) into `out`. Returns false, with `out` in an
// unspecified state, when the bytes are not a valid Msg (wrong hash, short, bad lengths).
template <class Msg>
bool DecodeMessage(Msg& out, const void* data, int size) {
    if (data == nullptr || size < 0) return false;
    try {
        return out.decode(data, 0, size) >= 0;
    } catch (const std::exception&) {
        return false;
    }
}

}  // namespace gyrocal::bus
