#pragma once
// gyrocal-plateau: the LCM shell around PlateauDetector (one per sensor) and TableMotion.
//
// Threads: one. Bus::Handle dispatches GYRO_*, ENCODER, CHAMBER_STATE and RUN_EVENT on the Run()
// thread. A gyro sample waits in its sensor's queue until the encoder has spoken about its
// moment +- the motion guard (or the encoder is stale), then it is classified still/moving and
// fed to the sensor's detector; plateaus and state reports are published at once. The same
// classified samples feed the sensor's noise tracker (processors/noise: the Allan deviation of
// its still, thermally quiet stretches): NOISE_<id> goes out every noise_period_s of data time,
// just before each PLATEAU_<id> (so the fitter has the estimate up to that plateau), and at the
// run's stop. Processors use message time only: nothing here reads a clock except the STATUS
// heartbeat.
#include <cstdint>
#include <deque>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "gyrocal/chamber_state_t.hpp"
#include "gyrocal/gyro_sample_t.hpp"
#include "gyrocal/run_event_t.hpp"
#include "processors/motion/node/motion_inputs.hpp"
#include "processors/motion/node/motion_node.hpp"
#include "processors/motion/table_motion.hpp"
#include "processors/noise/noise_tracker.hpp"
#include "processors/plateau/plateau_detector.hpp"

namespace gyrocal::plateau::node {

struct PlateauOptions {
    std::string lcm_url;               // "" = $GYROCAL_LCM_URL or the default
    std::vector<std::string> sensors;  // accepted sensor ids; empty = every valid id
    std::string encoder_id = "TABLE";  // encoder whose motion matters
    plateau::PlateauConfig detector = plateau::PlateauConfig::Defaults();
    motion::MoveDetectorConfig move = motion::MoveDetectorConfig::Defaults();
    // [s] a sample this close to table motion is "moving"
    double motion_guard_s = motion::kDefaultGuardS;
    double encoder_stale_s = 2.0;  // [s] decide without the encoder once a stream is this far ahead
    noise::TrackerConfig noise = noise::TrackerConfig::Defaults();
    double noise_period_s = 60.0;  // [s] of data time between NOISE_<id> messages
    static PlateauOptions Defaults() { return {}; }
    // "" when valid, else a one-line error naming the option and its valid range.
    std::string Validate() const;
};

// Its bus, STATUS, inputs, Run() and test hooks are MotionNode's.
class PlateauNode : public motion::node::MotionNode {
public:
    explicit PlateauNode(const PlateauOptions& options);  // throws BusError when LCM cannot open
    int64_t plateaus_published() const { return plateaus_; }

private:
    struct Sensor {
        Sensor(const plateau::PlateauConfig& c, const noise::TrackerConfig& n)
            : detector(c), noise(n) {}
        plateau::PlateauDetector detector;
        noise::NoiseTracker noise;
        int64_t last_noise_utime = 0;
        std::deque<plateau::Sample> pending;
        motion::node::StreamTime time;
    };
    void OnGyro(const std::string& id, const gyro_sample_t& msg,
                const std::string& channel) override;
    void OnEncoder(const motion::EncoderReading& reading) override;
    void OnChamberState(const chamber_state_t& msg);
    void OnRunEvent(const run_event_t& msg) override;
    Sensor& SensorFor(const std::string& id);
    void Drain(const std::string& id, Sensor& sensor);
    void DrainAll();
    void Publish(const std::string& id, const plateau::Step& step);
    void PublishNoise(const std::string& id, Sensor& sensor);

    PlateauOptions options_;
    motion::TableMotion motion_;
    std::map<std::string, std::unique_ptr<Sensor>> sensors_;
    std::string run_id_;
    double chamber_setpoint_c_;
    motion::node::StreamTime chamber_time_;
    int64_t plateaus_ = 0;
    int64_t refused_ = 0;  // averaging windows refused for a sequence gap
};

}  // namespace gyrocal::plateau::node
