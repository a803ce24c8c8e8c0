#pragma once
// What a harness asserts beyond "does not crash". FUZZ_CHECK prints the contract that broke and
// aborts: libFuzzer reports it as a crash and saves the input; the replay test (replay_test.cpp)
// dies on it, so ctest fails and names the input it was replaying.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>

#include "lcmtypes/channels/channels.hpp"
#include "producers/csv/row_parser.hpp"

#define FUZZ_CHECK(cond, what)                                                                    \
    do {                                                                                          \
        if (!(cond)) {                                                                            \
            std::fprintf(stderr, "fuzz contract broken: %s (%s:%d)\n", what, __FILE__, __LINE__); \
            std::abort();                                                                         \
        }                                                                                         \
    } while (0)

namespace gyrocal::fuzz {

// A row that csv::RowParser accepted is one the format allows (producers/csv_source/README.md):
// finite values, a valid sensor id, time_s in range and strictly increasing per sensor on the
// microsecond grid. `last_us` holds the previous time of each sensor.
inline void CheckRow(const csv::CsvRow& r, std::map<std::string, long long>& last_us) {
    FUZZ_CHECK(channels::IsValidSensorId(r.sensor_id), "row with an invalid sensor_id");
    FUZZ_CHECK(std::isfinite(r.time_s) && std::fabs(r.time_s) <= csv::kMaxAbsTimeS,
               "row with time_s not finite or out of range");
    FUZZ_CHECK(std::isfinite(r.gyro_v) && std::isfinite(r.temp_v) && std::isfinite(r.temp_c),
               "row with a non-finite gyro_v, temp_v or temp_c");
    for (const auto& opt : {r.supply_v, r.encoder_deg, r.chamber_c}) {
        FUZZ_CHECK(!opt || std::isfinite(*opt), "row with a non-finite optional field");
    }
    const long long us = csv::TimeUs(r.time_s);
    const auto it = last_us.find(r.sensor_id);
    FUZZ_CHECK(it == last_us.end() || us > it->second, "time_s not increasing per sensor");
    last_us[r.sensor_id] = us;
}

}  // namespace gyrocal::fuzz
