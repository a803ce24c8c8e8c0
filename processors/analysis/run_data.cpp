#include "processors/analysis/run_data.hpp"

#include <algorithm>
#include <cmath>
#include <set>

namespace gyrocal::analysis {

std::vector<motion::TableMove> MovesFromEncoder(std::vector<motion::EncoderReading> enc,
                                                const BuildOptions& o, int64_t* n_bad) {
    std::stable_sort(enc.begin(), enc.end(),
                     [](const motion::EncoderReading& a, const motion::EncoderReading& b) {
                         return a.utime < b.utime;
                     });
    std::vector<motion::TableMove> moves;
    motion::MoveDetector detector(o.move);
    int64_t last = INT64_MIN, bad = 0;
    for (const motion::EncoderReading& e : enc) {
        if (e.utime <= last || e.counts_per_rev <= 0) {  // as the live node guards
            ++bad;
            continue;
        }
        last = e.utime;
        if (auto m = detector.Feed({e.utime, e.counts, e.counts_per_rev})) moves.push_back(*m);
    }
    if (n_bad) *n_bad = bad;
    // A move still under way when the readings end lasts to the last reading.
    if (const auto m = detector.MoveUnderWay(last)) moves.push_back(*m);
    return moves;
}

namespace {

void PowerOn(SensorRun& run, const std::vector<PowerRecord>& power) {
    std::set<int64_t> on;
    std::set<std::string> sources;
    for (const PowerRecord& p : power) {
        on.insert(p.power_on_utime);
        sources.insert(p.source.empty() ? "unnamed" : p.source);
    }
    run.power_on_utimes.assign(on.begin(), on.end());
    run.power_on_assumed = on.empty();
    if (run.power_on_assumed) {
        run.power_on_source = "assumed: the unit's first sample (no power-on record)";
        return;
    }
    std::string list;
    for (const std::string& s : sources) list += (list.empty() ? "" : ", ") + s;
    run.power_on_source = std::to_string(on.size()) + " power-on record" +
                          (on.size() > 1 ? "s" : "") + " (" + list + ")";
}

}  // namespace

SensorRun BuildSensorRun(const std::string& sensor_id, std::vector<GyroSample> raw,
                         const std::vector<motion::EncoderReading>& encoder,
                         std::vector<PlateauInput> plateaus,
                         std::vector<SensitivityInput> sensitivities,
                         const std::vector<PowerRecord>& power, const BuildOptions& o) {
    SensorRun run;
    run.sensor_id = sensor_id;
    run.plateaus = std::move(plateaus);
    run.sensitivities = std::move(sensitivities);
    run.n_raw_samples = static_cast<int64_t>(raw.size());
    run.has_encoder = !encoder.empty();
    run.moves = MovesFromEncoder(encoder, o, &run.n_bad_encoder);
    // Fewer than 2 usable readings cannot show a move: motion unknown (run_data.hpp).
    run.motion_unknown =
        run.has_encoder && static_cast<int64_t>(encoder.size()) - run.n_bad_encoder < 2;
    const auto first =
        std::min_element(encoder.begin(), encoder.end(),
                         [](const motion::EncoderReading& a, const motion::EncoderReading& b) {
                             return a.utime < b.utime;
                         });
    if (first != encoder.end() && first->counts_per_rev > 0)
        run.initial_counts = first->counts, run.counts_per_rev = first->counts_per_rev;
    PowerOn(run, power);
    std::stable_sort(raw.begin(), raw.end(),
                     [](const GyroSample& a, const GyroSample& b) { return a.utime < b.utime; });
    if (!raw.empty()) run.first_sample_utime = raw.front().utime;
    const auto guard_us = static_cast<int64_t>(o.guard_s * 1e6);
    size_t m = 0;  // first move whose guarded end is not before the sample
    int64_t last_utime = INT64_MIN, last_seq = -1;
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
        while (m < run.moves.size() && run.moves[m].end_utime + guard_us < s.utime) ++m;
        const bool moving = m < run.moves.size() && run.moves[m].Near(s.utime, guard_us);
        run.samples.push_back(s);
        run.still.push_back(moving ? 0 : 1);
        if (moving) ++run.n_moving_samples;
    }
    return run;
}

void AddChamberAir(SensorRun& run, std::vector<AirSample> air) {
    std::stable_sort(air.begin(), air.end(),
                     [](const AirSample& a, const AirSample& b) { return a.utime < b.utime; });
    run.air.clear();
    for (const AirSample& a : air) {
        if (!std::isfinite(a.air_c) || (!run.air.empty() && a.utime <= run.air.back().utime)) {
            ++run.n_bad_air;
            continue;
        }
        run.air.push_back(a);
    }
}

}  // namespace gyrocal::analysis
