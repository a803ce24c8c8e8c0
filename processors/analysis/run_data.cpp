#include "run_data.hpp"

#include <algorithm>
#include <cmath>

namespace gyrocal::analysis {

std::vector<MotionInterval> MotionFromEncoder(std::vector<EncoderSample> enc,
                                              const BuildOptions& o) {
    std::sort(enc.begin(), enc.end(),
              [](const EncoderSample& a, const EncoderSample& b) { return a.utime < b.utime; });
    std::vector<MotionInterval> out;
    const auto merge_us = static_cast<int64_t>(o.merge_gap_s * 1e6);
    for (size_t i = 1; i < enc.size(); ++i) {
        const double d = enc[i].angle_deg - enc[i - 1].angle_deg;
        if (!std::isfinite(d) || std::fabs(d) <= o.min_move_deg) continue;
        if (!out.empty() && enc[i - 1].utime - out.back().end_utime <= merge_us) {
            out.back().end_utime = enc[i].utime;
            out.back().angle_change_deg += d;
        } else {
            out.push_back({enc[i - 1].utime, enc[i].utime, d});
        }
    }
    return out;
}

SensorRun BuildSensorRun(const std::string& sensor_id, std::vector<GyroSample> raw,
                         const std::vector<EncoderSample>& encoder,
                         std::vector<PlateauInput> plateaus,
                         std::vector<SensitivityInput> sensitivities, const BuildOptions& o) {
    SensorRun run;
    run.sensor_id = sensor_id;
    run.plateaus = std::move(plateaus);
    run.sensitivities = std::move(sensitivities);
    run.n_raw_samples = static_cast<int64_t>(raw.size());
    run.has_encoder = !encoder.empty();
    run.motion = MotionFromEncoder(encoder, o);
    std::stable_sort(raw.begin(), raw.end(),
                     [](const GyroSample& a, const GyroSample& b) { return a.utime < b.utime; });
    if (!raw.empty()) run.first_sample_utime = raw.front().utime;
    const auto guard_us = static_cast<int64_t>(o.guard_s * 1e6);
    size_t m = 0;  // first motion interval whose guarded end is not before the sample
    int64_t last_utime = INT64_MIN;
    int64_t last_seq = -1;
    bool have_seq = false;
    for (const GyroSample& s : raw) {
        if (have_seq && s.seq > last_seq + 1) run.n_seq_gaps += s.seq - last_seq - 1;
        if (!have_seq || s.seq > last_seq) last_seq = s.seq;
        have_seq = true;
        if (!std::isfinite(s.temp_c) || !std::isfinite(s.gyro_v) || s.utime <= last_utime) {
            ++run.n_bad_samples;
            continue;
        }
        last_utime = s.utime;
        while (m < run.motion.size() && run.motion[m].end_utime + guard_us < s.utime) ++m;
        if (m < run.motion.size() && s.utime >= run.motion[m].start_utime - guard_us) {
            ++run.n_moving_samples;
            continue;
        }
        run.still.push_back(s);
    }
    return run;
}

}  // namespace gyrocal::analysis
