#include "processors/rotation/node/rotation_message.hpp"

namespace gyrocal::rotation::node {

sensitivity_point_t ToMessage(const std::string& sensor_id, const std::string& run_id,
                              const rotation::Point& p) {
    sensitivity_point_t m;
    m.utime = p.end_utime;
    m.sensor_id = sensor_id;
    m.run_id = run_id;
    m.rotation_id = p.rotation_id;
    m.start_utime = p.start_utime;
    m.end_utime = p.end_utime;
    m.first_seq = p.first_seq;
    m.last_seq = p.last_seq;
    m.n_samples = p.n_samples;
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
