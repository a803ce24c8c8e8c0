#include "tests/processors/analysis/sim_run.hpp"

#include <cmath>

namespace gyrocal::analysis::testing {

namespace {

class Collector : public sim::RigSink {
public:
    Collector(sim::Rig& rig, sim::BuiltinProfile& profile, const SimRunOptions& o,
              int64_t start_utime)
        : rig_(rig), profile_(profile), o_(o), start_utime_(start_utime) {}
    void OnGyro(const sim::GyroReading& r, const sim::GyroTruth& truth) override {
        if (r.unit_index != 0) return;
        const double t_s = (r.utime - start_utime_) * 1e-6;
        double extra = o_.outside_v ? o_.outside_v(t_s) : 0.0;
        if (o_.outside_channels_v)
            extra += o_.outside_channels_v({t_s, r.temp_c, air_c_, table_deg_});
        gyro.push_back({.utime = r.utime,
                        .seq = r.seq,
                        .gyro_v = r.gyro_v + extra,
                        .temp_c = r.temp_c,
                        .supply_v = o_.record_supply ? r.supply_v : kNan});
        const sim::UnitTruth& u = rig_.units()[0];
        effect_v.push_back(truth.effect_offset_v + extra);
        truth_v.push_back(u.OffsetV(r.temp_c - u.temp_sensor_offset_c) + effect_v.back());
    }
    void OnEncoder(const sim::EncoderReading& r) override {
        encoder.push_back({r.utime, r.counts, r.counts_per_rev});
        if (r.counts_per_rev > 0)
            table_deg_ = static_cast<double>(r.counts) * 360.0 / r.counts_per_rev;
    }
    void OnChamber(const sim::ChamberReading& r) override {
        profile_.OnChamber(r, rig_);
        const double t_s = (r.utime - start_utime_) * 1e-6;
        air_c_ = r.air_c + (o_.air_offset_c ? o_.air_offset_c(t_s) : 0.0);
        if (o_.record_air) air.push_back({r.utime, air_c_});
    }
    std::vector<GyroSample> gyro;
    std::vector<double> truth_v, effect_v;  // SimRun::truth_offset_v, effect_offset_v
    std::vector<motion::EncoderReading> encoder;
    std::vector<AirSample> air;

private:
    sim::Rig& rig_;
    sim::BuiltinProfile& profile_;
    const SimRunOptions& o_;
    int64_t start_utime_;
    double air_c_ = kNan, table_deg_ = 0.0;
};

struct Stats {
    double mean = 0, sem = 0;
    int n = 0;
};

// Mean of samples in [t0, t1) and its standard error from 1 s block means (the samples are
// correlated by the module's low-pass filter and the slow noise; blocks make that honest enough).
Stats WindowStats(const std::vector<GyroSample>& s, int64_t t0, int64_t t1, bool temp) {
    Stats st;
    std::vector<double> blocks;
    double bsum = 0;
    int bn = 0;
    int64_t bstart = t0;
    double sum = 0;
    for (const GyroSample& g : s) {
        if (g.utime < t0) continue;
        if (g.utime >= t1) break;
        const double v = temp ? g.temp_c : g.gyro_v;
        sum += v;
        ++st.n;
        if (g.utime - bstart >= 1'000'000) {
            if (bn > 0) blocks.push_back(bsum / bn);
            bsum = 0;
            bn = 0;
            bstart = g.utime;
        }
        bsum += v;
        ++bn;
    }
    if (bn > 0) blocks.push_back(bsum / bn);
    if (st.n == 0) return st;
    st.mean = sum / st.n;
    double ss = 0, bm = 0;
    for (double b : blocks) bm += b;
    bm /= blocks.size();
    for (double b : blocks) ss += (b - bm) * (b - bm);
    st.sem = blocks.size() > 1 ? std::sqrt(ss / (blocks.size() - 1) / blocks.size()) : 0.0;
    return st;
}

}  // namespace

SimRun MakeSimRun(const SimRunOptions& o, bool keep_raw) {
    SimRun out;
    sim::RigConfig c = sim::RigConfig::Defaults();
    c.seed = o.seed;
    c.noise_seed = o.noise_seed;
    if (o.start_utime != 0) c.start_utime = o.start_utime;
    c.num_units = 1;
    c.effects = o.effects;
    c.thermal.ramp_c_per_min = o.ramp_c_per_min;
    c.thermal.package_tau_s = o.package_tau_s;
    c.thermal.air_tau_s = o.air_tau_s;
    c.thermal.sensor_tau_s = o.sensor_tau_s;
    out.config = c;
    sim::Rig rig(c);
    out.truth = rig.units()[0];
    sim::ProfileConfig pc;
    pc.setpoints_c = o.setpoints_c;
    pc.dwell_s = o.dwell_s;
    pc.rest_s = o.rest_s;
    pc.move_deg = 90.0;
    sim::BuiltinProfile profile(pc);
    Collector col(rig, profile, o, c.start_utime);
    const int64_t step = 60'000'000;
    int64_t until = c.start_utime;
    while (!profile.done() && until < c.start_utime + int64_t{40'000} * 1'000'000) {
        until += step;
        rig.RunUntil(until, col);
    }
    out.duration_s = (until - c.start_utime) * 1e-6;

    // Plateau windows: the end of each dwell, which ends at the first (+) move of its setpoint.
    const std::vector<motion::TableMove> moves =
        MovesFromEncoder(col.encoder, BuildOptions::Defaults());
    std::vector<int64_t> dwell_ends;
    for (size_t i = 0; i < moves.size(); i += 2)
        dwell_ends.push_back(moves[i].start_utime - 1'000'000);
    std::vector<PlateauInput> plateaus;
    for (int64_t end : dwell_ends) {
        const auto start = end - static_cast<int64_t>(o.plateau_window_s * 1e6);
        const Stats t = WindowStats(col.gyro, start, end, true),
                    v = WindowStats(col.gyro, start, end, false);
        plateaus.push_back({.plateau_id = start,
                            .start_utime = start,
                            .end_utime = end,
                            .temp_mean_c = t.mean,
                            .temp_sem_c = t.sem,
                            .gyro_mean_v = v.mean,
                            .gyro_sem_v = v.sem,
                            .n_samples = v.n});
    }
    std::vector<SensitivityInput> sens;
    const int64_t guard = 1'000'000, rest = 5'000'000;
    for (const motion::TableMove& m : moves) {
        const Stats pre =
            WindowStats(col.gyro, m.start_utime - guard - rest, m.start_utime - guard, false);
        const Stats post =
            WindowStats(col.gyro, m.end_utime + guard, m.end_utime + guard + rest, false);
        const Stats temp = WindowStats(col.gyro, m.start_utime - guard, m.end_utime + guard, true);
        if (pre.n == 0 || post.n == 0) continue;
        const double offset = 0.5 * (pre.mean + post.mean);
        double integral = 0;
        int64_t prev = -1;
        for (const GyroSample& g : col.gyro) {
            if (g.utime < m.start_utime - guard) continue;
            if (g.utime > m.end_utime + guard) break;
            if (prev >= 0) integral += (g.gyro_v - offset) * (g.utime - prev) * 1e-6;
            prev = g.utime;
        }
        const double dur_s = (m.end_utime - m.start_utime + 2 * guard) * 1e-6;
        // Noise of the integral: 1 s block scatter (sem * sqrt(blocks) = block sd) times sqrt(dur);
        // offset error times the duration.
        const double block_sd = 0.5 * (pre.sem + post.sem) * std::sqrt(5.0);
        const double sem_off = 0.5 * std::hypot(pre.sem, post.sem);
        const double sd_int = std::hypot(block_sd * std::sqrt(dur_s), sem_off * dur_s);
        SensitivityInput s;
        s.rotation_id = m.start_utime;
        s.utime = m.end_utime;
        s.temp_c = temp.mean;
        s.direction = m.angle_deg() > 0 ? 1 : -1;
        s.sensitivity_v_per_dps = integral / m.angle_deg();
        s.stderr_v_per_dps = sd_int / std::fabs(m.angle_deg());
        sens.push_back(s);
    }
    if (keep_raw) {
        out.raw = col.gyro;
        out.encoder = col.encoder;
    }
    // The rig powers its units when it starts (the rig process announces it on POWER_<id>).
    out.power = {{c.start_utime, c.start_utime, "rig"}};
    out.truth_offset_v = std::move(col.truth_v);
    out.effect_offset_v = std::move(col.effect_v);
    out.run = BuildSensorRun(out.truth.sensor_id, std::move(col.gyro), col.encoder,
                             std::move(plateaus), std::move(sens), out.power);
    out.air = col.air;
    AddChamberAir(out.run, std::move(col.air));
    return out;
}

}  // namespace gyrocal::analysis::testing
