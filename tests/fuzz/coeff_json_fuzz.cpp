// Fuzz the coefficient file of `gyrocal compensate`: a text through
// compensator::CoeffSetsFromJson, and the sets it accepts through compensator::CompensateRows on a
// few samples of each sensor (ramping temperature, so the dT/dt inputs move), as the command runs
// them.
// Contract: only compensator::OfflineError is thrown (the command prints it and exits non-zero);
// every accepted set is keyed by its own sensor_id; every rate that comes out belongs to a row
// that went in.
#include <cstdint>
#include <string>
#include <vector>

#include "processors/compensator/offline.hpp"
#include "tests/fuzz/fuzz_check.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace gyrocal;
    const std::string text(reinterpret_cast<const char*>(data), size);
    std::map<std::string, model::CoeffSet> sets;
    try {
        sets = compensator::CoeffSetsFromJson(text, "fuzz.json");
    } catch (const compensator::OfflineError&) {
        return 0;
    }
    std::vector<csv::CsvRow> rows;
    for (const auto& [id, set] : sets) {
        FUZZ_CHECK(set.sensor_id == id, "a set filed under another sensor's id");
        if (!channels::IsValidSensorId(id)) continue;  // a CSV row cannot name it
        for (int i = 0; i < 50; ++i) {
            csv::CsvRow r;
            r.line = static_cast<long>(rows.size()) + 2;
            r.time_s = 0.1 * i;
            r.sensor_id = id;
            r.gyro_v = 2.5;
            r.temp_v = 2.5 + 0.009 * 0.2 * i;
            r.temp_c = 25.0 + 0.2 * i;
            r.supply_v = 5.0;
            rows.push_back(r);
        }
    }
    try {
        const compensator::OfflineResult res =
            compensator::CompensateRows(rows, sets, "fuzz.csv", "fuzz.json");
        FUZZ_CHECK(res.rates.size() + static_cast<size_t>(res.skipped) == rows.size(),
                   "rates + skipped != rows");
    } catch (const compensator::OfflineError&) {
    }
    return 0;
}
