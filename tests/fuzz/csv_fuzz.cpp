// Fuzz the CSV path of gyrocal-csv-source and `gyrocal compensate`: a whole text through
// csv::ReadCsv (header, row parser) under both policies, and each row through
// csv::MessageBuilder into the messages a CSV source publishes.
// Contract: only csv::CsvError is thrown; every row that comes out is one the format allows
// (fuzz::CheckRow); "stop" and "skip" agree (stop succeeds exactly when skip skipped nothing,
// with the same rows); the messages encode and decode, with seq counting per sensor from 0.
#include <algorithm>
#include <cstdint>
#include <sstream>
#include <string>
#include <vector>

#include "lcmtypes/bus/decode.hpp"
#include "producers/csv/csv_file.hpp"
#include "producers/csv/row_messages.hpp"
#include "tests/fuzz/fuzz_check.hpp"

namespace {

using namespace gyrocal;

template <class Msg>
void CheckEncodes(const Msg& m) {
    std::vector<uint8_t> buf(static_cast<size_t>(m.getEncodedSize()));
    FUZZ_CHECK(m.encode(buf.data(), 0, static_cast<int>(buf.size())) > 0,
               "message does not encode");
    Msg back{};
    FUZZ_CHECK(bus::DecodeMessage(back, buf.data(), static_cast<int>(buf.size())),
               "message does not decode");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    const sensor::TempTransfer transfer;
    csv::CsvFile skip;
    try {
        std::istringstream in(text);
        skip = csv::ReadCsv(in, "fuzz.csv", transfer, csv::OnError::kSkip);
    } catch (const csv::CsvError&) {
        return 0;  // no valid header: stop fails the same way
    }
    FUZZ_CHECK(static_cast<long>(skip.errors.size()) ==
                   std::min<long>(skip.skipped, csv::CsvReader::kKeptErrors),
               "skip count != messages (the first kKeptErrors are kept)");
    try {
        std::istringstream in(text);
        const csv::CsvFile stop = csv::ReadCsv(in, "fuzz.csv", transfer, csv::OnError::kStop);
        FUZZ_CHECK(skip.skipped == 0 && stop.rows.size() == skip.rows.size(),
                   "stop accepted a file that skip had to skip rows of");
    } catch (const csv::CsvError&) {
        FUZZ_CHECK(skip.skipped > 0, "stop refused a file that skip read whole");
    }

    std::map<std::string, long long> last_us;
    std::map<std::string, int64_t> next_seq;
    csv::MessageBuilder builder;
    for (const csv::CsvRow& row : skip.rows) {
        fuzz::CheckRow(row, last_us);
        const csv::RowMessages m =
            builder.Build(row, csv::StreamUtime(csv::kDefaultStartUtime, row.time_s));
        FUZZ_CHECK(m.gyro.seq == next_seq[row.sensor_id]++, "gyro seq does not count per sensor");
        CheckEncodes(m.gyro);
        if (m.encoder) CheckEncodes(*m.encoder);
        if (m.chamber) CheckEncodes(*m.chamber);
    }
    return 0;
}
