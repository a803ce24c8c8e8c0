#pragma once
// What a non-real-time source sends through: gyro and encoder samples gathered per channel and
// published as batches (batch.hpp), at most `max_samples` per batch.
//
// Order: a flush publishes the encoder's batch first, then each gyro channel's in the order
// the channels first appeared, so a consumer has the table angle of a time before the gyro
// samples of that time (as the CSV source always sent them). A message that is not batched
// (chamber state, power-on, run events) must go out after Flush(), so that no channel overtakes
// another by more than one batch. max_samples <= 1 publishes every sample at once, alone.
#include <cstddef>
#include <string>
#include <vector>

#include "lcmtypes/bus/bus.hpp"

namespace gyrocal::bus {

class SampleBatcher {
public:
    SampleBatcher(Bus& bus, int max_samples) : bus_(bus), max_(max_samples) {}

    void Add(const std::string& channel, const gyro_sample_t& m);
    void AddEncoder(const std::string& channel, const encoder_sample_t& m);
    // Publishes everything held (encoder first). Returns false when a publish failed.
    bool Flush();
    bool full() const { return full_; }
    size_t held() const { return held_; }
    int max_samples() const { return max_; }

private:
    struct Gyros {
        std::string channel;
        std::vector<gyro_sample_t> samples;
    };
    Bus& bus_;
    int max_;
    std::string encoder_channel_;
    std::vector<encoder_sample_t> encoders_;
    std::vector<Gyros> gyros_;  // a handful of units: linear search beats a map
    size_t held_ = 0;
    bool full_ = false;
};

}  // namespace gyrocal::bus
