#pragma once
// What gyrocal-plateau and gyrocal-rotation are around their own processing, once: the bus, the
// STATUS reporter and the checked GYRO_*/ENCODER/RUN_EVENT inputs (MotionInputs, whose handlers
// the node overrides), the run loop, and the hooks the tests drive a node in-process with.
//
// Threads: one. Bus::Handle dispatches on the Run() thread.
#include <string>
#include <vector>

#include "lcmtypes/bus/bus.hpp"
#include "lcmtypes/process/status.hpp"
#include "processors/motion/node/motion_inputs.hpp"

namespace gyrocal::motion::node {

// Privately a MotionInputs::Handler: only its own MotionInputs calls the On* handlers.
class MotionNode : private MotionInputs::Handler {
public:
    // Opens the bus at `lcm_url` (throws BusError when LCM cannot open), reports STATUS as
    // `process` and subscribes the inputs of `sensors` (empty = every valid id) and `encoder_id`.
    MotionNode(const std::string& process, const std::string& lcm_url,
               const std::vector<std::string>& sensors, const std::string& encoder_id);
    void Run();
    // Tests drive the node in-process over memq://: they publish into its bus, dispatch with
    // Handle, and see its STATUS (counters, per-sensor state) after PublishStatus.
    bus::Bus& bus() { return bus_; }
    void PublishStatus() { status_.PublishNow(); }

protected:
    ~MotionNode() = default;

    bus::Bus bus_;
    process::StatusReporter status_;

private:
    MotionInputs inputs_;
};

}  // namespace gyrocal::motion::node
