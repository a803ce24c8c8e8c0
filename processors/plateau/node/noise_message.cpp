#include "processors/plateau/node/noise_message.hpp"

#include "processors/motion/node/result_fields.hpp"

namespace gyrocal::plateau::node {

noise_t ToNoiseMessage(const std::string& sensor_id, const std::string& run_id,
                       const noise::NoiseEstimate& e) {
    noise_t m{};
    motion::node::Stamp(m, e.utime, sensor_id, run_id);
    m.still_s = e.still_s;
    m.n_segments = e.segments;
    m.longest_segment_s = e.longest_s;
    m.tau0_s = e.tau0_s;
    m.arw_v_rthz = e.terms.arw;
    m.arw_stderr_v_rthz = e.terms.arw_se;
    m.bias_instability_v = e.terms.bias;
    m.bias_instability_stderr_v = e.terms.bias_se;
    m.rrw_v_rts = e.terms.rrw;
    m.rrw_stderr_v_rts = e.terms.rrw_se;
    m.fit_note = e.terms.note;
    for (const noise::AllanPoint& p : e.adev) {
        m.tau_s.push_back(p.tau_s);
        m.adev_v.push_back(p.adev);
        m.adev_lo_v.push_back(p.adev_lo);
        m.adev_hi_v.push_back(p.adev_hi);
        m.edf.push_back(p.edf);
    }
    m.num_taus = static_cast<int32_t>(m.tau_s.size());
    return m;
}

}  // namespace gyrocal::plateau::node
