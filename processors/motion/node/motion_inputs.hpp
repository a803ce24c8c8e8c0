#pragma once
// The bus inputs gyrocal-plateau and gyrocal-rotation share: GYRO_<id> samples of the accepted
// sensors, the turntable's ENCODER readings and RUN_EVENT. Both nodes refuse the same messages
// the same way (each refusal counted in STATUS with its reason), so those checks live here once;
// a node's handlers get only what passed.
//
// Threads: none of its own; the handlers run on the thread that calls Bus::Handle().
#include <cstdint>
#include <exception>
#include <string>
#include <vector>

#include "gyrocal/encoder_sample_t.hpp"
#include "gyrocal/gyro_sample_t.hpp"
#include "gyrocal/run_event_t.hpp"
#include "lcmtypes/bus/bus.hpp"
#include "lcmtypes/process/status.hpp"
#include "processors/motion/table_motion.hpp"

namespace gyrocal::motion::node {

// Wraps a bus handler so that an exception never reaches LCM: it is counted as a refusal with
// its text.
template <class Fn>
auto Guarded(process::StatusReporter& status, Fn fn) {
    return [&status, fn](const auto& m, const std::string& channel) {
        try {
            fn(m, channel);
        } catch (const std::exception& e) {
            status.Reject("internal", channel + ": " + e.what());
        }
    };
}

// The newest utime of one message stream: a message not after it is refused as out-of-order.
class StreamTime {
public:
    // True when utime is after the newest so far; else counted in `status` as out-of-order.
    bool InOrder(int64_t utime, const std::string& stream, process::StatusReporter& status) const;
    void Advance(int64_t utime) {
        any_ = true;
        newest_utime_ = utime;
    }
    int64_t newest_utime() const { return newest_utime_; }  // [us] 0 before any

private:
    bool any_ = false;
    int64_t newest_utime_ = 0;
};

class MotionInputs {
public:
    // What the node does with the messages that passed.
    class Handler {
    public:
        // A sample of sensor `id`: its channel names a valid id, equal to its sensor_id and
        // accepted by --sensors.
        virtual void OnGyro(const std::string& id, const gyro_sample_t& msg,
                            const std::string& channel) = 0;
        // A reading of --encoder-id with counts_per_rev > 0, after the previous one.
        virtual void OnEncoder(const EncoderReading& reading) = 0;
        virtual void OnRunEvent(const run_event_t& msg) = 0;

    protected:
        ~Handler() = default;
    };

    // Subscribes GYRO_*, ENCODER and RUN_EVENT on `bus`; `sensors` empty = every valid id.
    MotionInputs(bus::Bus& bus, process::StatusReporter& status, std::vector<std::string> sensors,
                 std::string encoder_id, Handler& handler);
    // The subscriptions point at this object.
    MotionInputs(const MotionInputs&) = delete;
    MotionInputs& operator=(const MotionInputs&) = delete;

private:
    void OnGyro(const gyro_sample_t& m, const std::string& channel);
    void OnEncoder(const encoder_sample_t& m);

    process::StatusReporter& status_;
    std::vector<std::string> sensors_;
    std::string encoder_id_;
    Handler& handler_;
    StreamTime encoder_time_;
};

}  // namespace gyrocal::motion::node
