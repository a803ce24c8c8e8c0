#pragma once
// gyrocal-rotation: the LCM shell around one RotationEstimator per sensor and the shared
// turntable MoveDetector.
//
// Threads: one. Bus::Handle dispatches GYRO_*, ENCODER and RUN_EVENT on the Run() thread. Each
// completed move (from ENCODER) goes to every sensor's estimator; each sensor's point is
// published on SENSITIVITY_<id> as soon as the rest window after the move is complete (by gyro
// and encoder time). Message time only: no clock except the STATUS heartbeat.
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "gyrocal/gyro_sample_t.hpp"
#include "gyrocal/run_event_t.hpp"
#include "processors/motion/node/motion_inputs.hpp"
#include "processors/motion/node/motion_node.hpp"
#include "processors/motion/table_motion.hpp"
#include "processors/rotation/rotation_estimator.hpp"

namespace gyrocal::rotation::node {

struct RotationOptions {
    std::string lcm_url;               // "" = $GYROCAL_LCM_URL or the default
    std::vector<std::string> sensors;  // accepted sensor ids; empty = every valid id
    std::string encoder_id = "TABLE";
    rotation::RotationConfig estimator = rotation::RotationConfig::Defaults();
    motion::MoveDetectorConfig move = motion::MoveDetectorConfig::Defaults();
    static RotationOptions Defaults() { return {}; }
    // "" when valid, else a one-line error naming the option and its valid range.
    std::string Validate() const;
};

// Its bus, STATUS, inputs, Run() and test hooks are MotionNode's.
class RotationNode : public motion::node::MotionNode {
public:
    explicit RotationNode(const RotationOptions& options);  // throws BusError when LCM cannot open

private:
    struct Sensor {
        explicit Sensor(const rotation::RotationConfig& c) : estimator(c) {}
        rotation::RotationEstimator estimator;
        motion::node::StreamTime time;
    };
    void OnGyro(const std::string& id, const gyro_sample_t& msg,
                const std::string& channel) override;
    void OnEncoder(const motion::EncoderReading& reading) override;
    void OnRunEvent(const run_event_t& msg) override;
    void PollAndPublish(const std::string& id, Sensor& sensor);
    rotation::MotionView View() const;

    RotationOptions options_;
    motion::MoveDetector detector_;
    std::map<std::string, std::unique_ptr<Sensor>> sensors_;
    std::string run_id_;
    int64_t moves_ = 0, accepted_ = 0, refused_ = 0;
};

}  // namespace gyrocal::rotation::node
