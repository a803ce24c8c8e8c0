#include "processors/motion/node/motion_node.hpp"

namespace gyrocal::motion::node {

MotionNode::MotionNode(const std::string& process, const std::string& lcm_url,
                       const std::vector<std::string>& sensors, const std::string& encoder_id)
    : bus_(bus::BusOptions{lcm_url}),
      status_(bus_, process),
      inputs_(bus_, status_, sensors, encoder_id, *this) {}

void MotionNode::Run() {
    status_.set_state("running");
    // Malformed payloads (wrong type, hostile array lengths) are counted by the bus as decode
    // errors and never reach a handler; anything else thrown here is a bug and ends the process.
    process::RunLoop(bus_, status_);
}

}  // namespace gyrocal::motion::node
