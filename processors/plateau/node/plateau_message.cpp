#include "processors/plateau/node/plateau_message.hpp"

#include "processors/motion/node/result_fields.hpp"

namespace gyrocal::plateau::node {

plateau_t ToMessage(const std::string& sensor_id, const plateau::Plateau& p) {
    plateau_t m;
    motion::node::Stamp(m, p.end_utime, sensor_id, p.run_id);
    motion::node::CopyWindow(m, p);
    m.plateau_id = p.plateau_id;
    m.setpoint_c = p.setpoint_c;
    m.n_excluded_motion = p.n_excluded_motion;
    m.seq_gaps = p.seq_gaps;
    m.temp_mean_c = p.temp_c.mean;
    m.temp_std_c = p.temp_c.std;
    m.temp_sem_c = p.temp_c.sem;
    m.temp_slope_c_per_min = p.temp_slope_c_per_min;
    m.gyro_mean_v = p.gyro_v.mean;
    m.gyro_std_v = p.gyro_v.std;
    m.gyro_sem_v = p.gyro_v.sem;
    m.temp_mean_v = p.temp_mean_v;
    m.supply_mean_v = p.supply_mean_v;
    return m;
}

}  // namespace gyrocal::plateau::node
