#include "processors/rotation/node/rotation_message.hpp"

#include "processors/motion/node/result_fields.hpp"

namespace gyrocal::rotation::node {

sensitivity_point_t ToMessage(const std::string& sensor_id, const std::string& run_id,
                              const rotation::Point& p) {
    sensitivity_point_t m;
    motion::node::Stamp(m, p.end_utime, sensor_id, run_id);
    motion::node::CopyWindow(m, p);
    m.rotation_id = p.rotation_id;
    m.direction = p.direction;
    m.temp_c = p.temp_c;
    m.encoder_angle_deg = p.encoder_angle_deg;
    m.offset_v = p.offset_v;
    m.offset_stderr_v = p.offset_stderr_v;
    m.integral_v_s = p.integral_v_s;
    m.sensitivity_v_per_dps = p.sensitivity_v_per_dps;
    m.sensitivity_stderr_v_per_dps = p.sensitivity_stderr_v_per_dps;
    m.accepted = p.accepted;
    m.reject_reason = p.reject_reason;
    return m;
}

}  // namespace gyrocal::rotation::node
