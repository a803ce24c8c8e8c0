#pragma once
// What a measured-data source (the CSV and line sources) publishes, collected from its bus in
// the order it arrives: the samples of every unit, the encoder, the chamber and the power-on
// states; and how their node tests check it.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "gyrocal/chamber_state_t.hpp"
#include "gyrocal/encoder_sample_t.hpp"
#include "gyrocal/gyro_sample_t.hpp"
#include "gyrocal/power_state_t.hpp"
#include "lcmtypes/bus/bus.hpp"
#include "lcmtypes/channels/channels.hpp"
#include "producers/csv/row_messages.hpp"
#include "tests/lcmtypes/bus/bus_wait.hpp"

namespace gyrocal::testing {

struct SourceOutput {
    explicit SourceOutput(bus::Bus& bus) {
        CollectInto(bus, channels::AllSensors(channels::kGyroPrefix), gyro);
        CollectInto(bus, std::string(channels::kEncoder), encoder);
        CollectInto(bus, std::string(channels::kChamberState), chamber);
        CollectInto(bus, channels::AllSensors(channels::kPowerPrefix), power);
    }
    SourceOutput(const SourceOutput&) = delete;  // the subscriptions hold the vectors' addresses
    SourceOutput& operator=(const SourceOutput&) = delete;

    std::vector<gyro_sample_t> gyro;
    std::vector<encoder_sample_t> encoder;
    std::vector<chamber_state_t> chamber;
    std::vector<power_state_t> power;
};

// Dispatches until nothing more is pending (10 s at the most).
inline void DrainBus(bus::Bus& bus) {
    ASSERT_TRUE(HandleUntil(
        bus, [&] { return !bus.Handle(std::chrono::milliseconds(0)); },
        std::chrono::milliseconds(10'000), std::chrono::milliseconds(0)));
}

// The samples are the rows' (anything with `us`, `id` and `gyro_v`), in order: each row's unit,
// its time after csv::kDefaultStartUtime [us] and its gyro_v exactly, numbered per unit from 0;
// `more(sample, i)` checks the rest of sample i.
template <class Row, class More>
void ExpectSamplesOfRows(const std::vector<gyro_sample_t>& gyro, const std::vector<Row>& rows,
                         More more) {
    ASSERT_EQ(gyro.size(), rows.size());
    std::map<std::string, int64_t> seq;
    for (size_t i = 0; i < rows.size(); ++i) {
        SCOPED_TRACE(i);
        EXPECT_EQ(gyro[i].sensor_id, rows[i].id);
        EXPECT_EQ(gyro[i].utime, csv::kDefaultStartUtime + rows[i].us);
        EXPECT_EQ(gyro[i].gyro_v, rows[i].gyro_v);
        EXPECT_EQ(gyro[i].seq, seq[rows[i].id]++);
        more(gyro[i], i);
    }
}

}  // namespace gyrocal::testing
