#pragma once
// What a measured-data source (the CSV and line sources) publishes, collected from its bus in
// the order it arrives: the samples of every unit, the encoder, the chamber and the power-on
// states. The sources' node tests share it.
#include <string>
#include <vector>

#include "gyrocal/chamber_state_t.hpp"
#include "gyrocal/encoder_sample_t.hpp"
#include "gyrocal/gyro_sample_t.hpp"
#include "gyrocal/power_state_t.hpp"
#include "lcmtypes/bus/bus.hpp"
#include "lcmtypes/bus/channels.hpp"
#include "tests/lcmtypes/bus/bus_wait.hpp"

namespace gyrocal::testing {

struct SourceOutput {
    explicit SourceOutput(Bus& bus) {
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

}  // namespace gyrocal::testing
