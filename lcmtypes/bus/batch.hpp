#pragma once
// The batch form of each sample type (gyrocal/*_batch_t.lcm): several samples of one channel in
// one message, so that a fast non-real-time source costs every process on the bus one datagram
// per batch instead of one per sample. A batch travels on the channel of its samples; the bus
// unpacks it for a subscriber of the sample type (Bus::Subscribe), the recorder stores each
// sample as its own row, and lcm-spy shows the samples inside it.
#include <cstdint>
#include <cstring>
#include <utility>
#include <vector>

#include "gyrocal/encoder_batch_t.hpp"
#include "gyrocal/encoder_sample_t.hpp"
#include "gyrocal/gyro_batch_t.hpp"
#include "gyrocal/gyro_sample_t.hpp"
#include "gyrocal/rate_batch_t.hpp"
#include "gyrocal/rate_t.hpp"

namespace gyrocal::bus {

// Samples per batch that keep one gyro batch (and its LCM header) inside a 1500-byte Ethernet
// frame with sensor ids up to 8 characters: 16 x 73 B + 40 B. Larger batches still work (LCM
// sends up to 64 kB in one datagram), but are IP fragments on a LAN.
inline constexpr int kDefaultBatchSamples = 16;

template <class Msg>
struct BatchTraits;  // no batch form; each one below names its batch type

// The batch of `samples`: its time is the newest sample's, and so is its sensor id where the batch
// type has one (the encoder's has none).
template <class Batch, class Msg>
Batch MakeBatch(std::vector<Msg> samples) {
    Batch b;
    b.utime = samples.empty() ? 0 : samples.back().utime;
    if constexpr (requires { b.sensor_id; })
        b.sensor_id = samples.empty() ? "" : samples.back().sensor_id;
    b.num_samples = static_cast<int32_t>(samples.size());
    b.samples = std::move(samples);
    return b;
}

template <>
struct BatchTraits<gyro_sample_t> {
    using Batch = gyro_batch_t;
};

template <>
struct BatchTraits<encoder_sample_t> {
    using Batch = encoder_batch_t;
};

template <>
struct BatchTraits<rate_t> {
    using Batch = rate_batch_t;
};

template <class Msg>
concept HasBatch = requires {
    typename BatchTraits<Msg>::Batch;
};

// True when the payload starts with Msg's type hash (LCM writes it big-endian).
template <class Msg>
bool IsOfType(const void* data, int size) {
    if (data == nullptr || size < 8) return false;
    const auto* b = static_cast<const uint8_t*>(data);
    uint64_t v = 0;
    for (int i = 0; i < 8; ++i) v = (v << 8) | b[i];
    return v == static_cast<uint64_t>(Msg::getHash());
}

}  // namespace gyrocal::bus
