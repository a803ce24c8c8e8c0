// Fuzz the recorder's view of the bus: a sequence of received messages through
// recorder::RecordMapper::Map, as gyrocal-recorder maps every message it receives (fingerprint,
// decode, run in force, seq gaps).
// Input: records of [channel: 1 byte, an index into kChannels][length: 2 bytes, big-endian]
// [payload: length bytes]; a record cut short by the end of the input takes what is left.
// Contract: Map never throws; every message becomes a row (a batch one per sample; flow control
// and an empty batch none, said by `control`); a message that is unknown or does not decode is
// kept whole as a raw event, and a decode error is counted exactly for a known
// fingerprint that does not decode; only a run event changes the run in force.
#include <cstdint>
#include <string>
#include <vector>

#include "lcmtypes/channels/channels.hpp"
#include "store/recorder/record_mapper.hpp"
#include "tests/fuzz/fuzz_check.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace gyrocal;
    static const std::vector<std::string> kChannels = {channels::Gyro("S01"),
                                                       std::string(channels::kEncoder),
                                                       std::string(channels::kChamberState),
                                                       std::string(channels::kRunEvent),
                                                       channels::Coeffs("S01"),
                                                       std::string(channels::kStatus),
                                                       channels::Plateau("S01"),
                                                       channels::Rate("S01"),
                                                       "SOMETHING_ELSE",
                                                       channels::Power("S01"),
                                                       channels::Noise("S01"),
                                                       channels::Fit("S01")};
    recorder::RecordMapper mapper(recorder::MapperOptions::Defaults(), "R0");
    size_t at = 0;
    int64_t recv_utime = 1;
    while (at < size) {
        const std::string& channel = kChannels[data[at] % kChannels.size()];
        size_t len = 0;
        if (at + 3 <= size) len = (static_cast<size_t>(data[at + 1]) << 8) | data[at + 2];
        at = std::min(size, at + 3);
        len = std::min(len, size - at);
        const uint8_t* payload = data + at;
        at += len;

        const std::string run_before = mapper.current_run();
        const recorder::Mapped m =
            mapper.Map(channel, payload, static_cast<int>(len), recv_utime++);
        if (m.control) {
            FUZZ_CHECK(!m.row && m.more.empty() && m.loss.decode_errors == 0,
                       "flow control or an empty batch became rows");
            FUZZ_CHECK(mapper.current_run() == run_before, "run changed without a run event");
            continue;
        }
        FUZZ_CHECK(m.row.has_value(), "a message became no row (rates are stored here)");
        for (const db::Row& r : m.more)
            FUZZ_CHECK(r.index() == m.row->index(), "a batch's rows are of different types");
        const auto* raw = std::get_if<db::RawEventRow>(&*m.row);
        if (m.loss.decode_errors > 0) {
            FUZZ_CHECK(raw && raw->reason == "decode_error", "decode error without its raw event");
        }
        if (raw) {
            FUZZ_CHECK(raw->data == std::vector<uint8_t>(payload, payload + len),
                       "raw event does not hold the message's bytes");
            FUZZ_CHECK((raw->reason == "decode_error") == (m.loss.decode_errors == 1),
                       "raw event reason and decode error count disagree");
        }
        if (!std::holds_alternative<db::RunEventRow>(*m.row)) {
            FUZZ_CHECK(mapper.current_run() == run_before, "run changed without a run event");
        }
    }
    return 0;
}
