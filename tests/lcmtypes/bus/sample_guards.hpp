#pragma once
// The bad input a process that consumes GYRO_<id> must count in its STATUS and survive, for the
// process tests of those processes (gyrocal-plateau, gyrocal-rotation): what each guard of its
// sample handler refuses (STYLE.md: decode, guard, count and skip).
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <string>

#include "gyrocal/encoder_sample_t.hpp"
#include "gyrocal/gyro_sample_t.hpp"
#include "lcmtypes/bus/bus.hpp"
#include "lcmtypes/channels/channels.hpp"
#include "tests/lcmtypes/bus/status_watch.hpp"
#include "tests/lcmtypes/bus/wire.hpp"
#include "tests/lcmtypes/message_builders.hpp"

namespace gyrocal::testing {

// A payload of another type on GYRO_X (a decode error); a sample at `utime` of `unknown_id`, a
// unit the process was not given; and one of `id` whose `nan_field` is NaN (two refusals).
inline void PublishBadSamples(bus::Bus& bus, int64_t utime, const std::string& unknown_id,
                              const std::string& id, double gyro_sample_t::*nan_field) {
    bus.Publish(channels::Gyro("X"), Encoder(0));
    gyro_sample_t bad = GyroSample(unknown_id, utime, 0, 1.0, 1.0);
    bus.Publish(channels::Gyro(unknown_id), bad);
    bad.sensor_id = id;
    bad.*nan_field = std::nan("");
    bus.Publish(channels::Gyro(id), bad);
}

// Publishes sample `seq` of `id` at `utime`, earlier than its newest, and waits (through `wire`,
// wire.hpp: the node in-process or the process over UDP) until STATUS shows `counted()` with
// that sample refused as out of order (its last refusal).
template <class Counted>
::testing::AssertionResult LateSampleIsRefused(bus::Bus& bus, const Wire& wire,
                                               const StatusWatch& watch, const std::string& id,
                                               int64_t utime, int64_t seq, Counted&& counted) {
    bus.Publish(channels::Gyro(id), GyroSample(id, utime, seq, 2.505, 30.0));
    if (!wire.until(counted, std::chrono::seconds(5))) {
        return ::testing::AssertionFailure()
               << "decode_errors " << watch.last.decode_errors << " rejected "
               << watch.last.rejected << " last_reject " << watch.last.last_reject;
    }
    if (watch.last.last_reject.find("out-of-order") == std::string::npos) {
        return ::testing::AssertionFailure() << "last_reject " << watch.last.last_reject;
    }
    return ::testing::AssertionSuccess();
}

}  // namespace gyrocal::testing
