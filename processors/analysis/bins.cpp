#include "bins.hpp"

#include <algorithm>
#include <cmath>

namespace gyrocal::analysis {

model::ModelInputs Bin::Inputs(int64_t first_sample_utime) const {
    model::ModelInputs in;
    in.temp_c = temp_c;
    in.dtemp_dt_c_per_s = dtemp_dt_c_per_s;
    in.supply_v = supply_v;
    in.heating = heating;
    in.time_since_power_s = (mid_utime - static_cast<double>(first_sample_utime)) * 1e-6;
    return in;
}

double SamplePeriodS(const SensorRun& run) {
    if (run.still.size() < 2) return 0.0;
    std::vector<int64_t> d;
    d.reserve(run.still.size() - 1);
    for (size_t i = 1; i < run.still.size(); ++i)
        d.push_back(run.still[i].utime - run.still[i - 1].utime);
    std::nth_element(d.begin(), d.begin() + static_cast<long>(d.size() / 2), d.end());
    return d[d.size() / 2] * 1e-6;
}

double BranchTracker::Update(double temp_c) {
    if (!std::isfinite(temp_c)) return branch_;
    if (!std::isfinite(memory_c_)) memory_c_ = temp_c;
    if (temp_c > memory_c_ + half_width_c_) {
        memory_c_ = temp_c - half_width_c_;
        branch_ = 1.0;
    } else if (temp_c < memory_c_ - half_width_c_) {
        memory_c_ = temp_c + half_width_c_;
        branch_ = -1.0;
    }
    return branch_;
}

namespace {

struct Acc {
    int64_t cell = -1;
    int n = 0, n_supply = 0;
    double t0_s = 0, st = 0, stt = 0, sT = 0, stT = 0, sv = 0, ss = 0;
    double sum_utime = 0;
};

}  // namespace

std::vector<Bin> MakeBins(const SensorRun& run, const BinOptions& o) {
    std::vector<Bin> bins;
    const double period_s = SamplePeriodS(run);
    if (period_s <= 0.0 || !(o.bin_s > 0.0)) return bins;
    const auto bin_us = static_cast<int64_t>(std::llround(o.bin_s * 1e6));
    const double expected = o.bin_s / period_s;
    const int64_t origin = run.first_sample_utime;
    int64_t last_cell = -2;
    int segment = -1;
    Acc a;
    auto flush = [&]() {
        if (a.n == 0 || a.n < o.min_fill * expected) return;
        Bin b;
        b.start_utime = origin + a.cell * bin_us;
        b.end_utime = b.start_utime + bin_us;
        b.n = a.n;
        b.mid_utime = a.sum_utime / a.n;
        b.temp_c = a.sT / a.n;
        b.gyro_v = a.sv / a.n;
        b.supply_v = a.n_supply == a.n ? a.ss / a.n : kNan;
        const double tm = a.st / a.n;
        const double sxx = a.stt - a.n * tm * tm;
        b.within_slope_c_per_s = sxx > 0 ? (a.stT - a.n * tm * b.temp_c) / sxx : kNan;
        if (a.cell != last_cell + 1) ++segment;
        b.segment = segment;
        last_cell = a.cell;
        bins.push_back(b);
    };
    for (const GyroSample& s : run.still) {
        const int64_t cell = (s.utime - origin) / bin_us;
        if (cell != a.cell) {
            flush();
            a = Acc{};
            a.cell = cell;
            a.t0_s = (origin + cell * bin_us) * 1e-6;
        }
        const double t = s.utime * 1e-6 - a.t0_s;  // seconds inside the cell: well conditioned
        ++a.n;
        a.sum_utime += static_cast<double>(s.utime);
        a.st += t;
        a.stt += t * t;
        a.sT += s.temp_c;
        a.stT += t * s.temp_c;
        a.sv += s.gyro_v;
        if (std::isfinite(s.supply_v)) {
            ++a.n_supply;
            a.ss += s.supply_v;
        }
    }
    flush();

    for (size_t i = 0; i < bins.size(); ++i) {
        const bool prev = i > 0 && bins[i - 1].segment == bins[i].segment;
        const bool next = i + 1 < bins.size() && bins[i + 1].segment == bins[i].segment;
        const Bin* lo = prev ? &bins[i - 1] : &bins[i];
        const Bin* hi = next ? &bins[i + 1] : &bins[i];
        if (lo != hi)
            bins[i].dtemp_dt_c_per_s =
                (hi->temp_c - lo->temp_c) / ((hi->mid_utime - lo->mid_utime) * 1e-6);
        else
            bins[i].dtemp_dt_c_per_s = bins[i].within_slope_c_per_s;
    }
    BranchTracker branch(o.branch_width_c);
    for (Bin& b : bins) b.heating = branch.Update(b.temp_c);
    for (size_t p = 0; p < run.plateaus.size(); ++p)
        for (Bin& b : bins)
            if (b.start_utime >= run.plateaus[p].start_utime &&
                b.end_utime <= run.plateaus[p].end_utime)
                b.plateau = static_cast<int>(p);
    return bins;
}

Floor NoiseFloor(const SensorRun& run, const std::vector<Bin>& bins, double bin_s,
                 const std::vector<double>* values) {
    Floor f;
    auto value = [&](size_t i) { return values ? (*values)[i] : bins[i].gyro_v; };
    double ss = 0.0;
    for (size_t p = 0; p < run.plateaus.size(); ++p) {
        double sum = 0.0;
        int n = 0;
        for (size_t i = 0; i < bins.size(); ++i)
            if (bins[i].plateau == static_cast<int>(p)) {
                sum += value(i);
                ++n;
            }
        if (n < 3) continue;
        const double mean = sum / n;
        for (size_t i = 0; i < bins.size(); ++i)
            if (bins[i].plateau == static_cast<int>(p)) ss += (value(i) - mean) * (value(i) - mean);
        f.dof += n - 1;
    }
    if (f.dof > 0) {
        f.offset_rms_v = std::sqrt(ss / f.dof);
        return f;
    }
    // sem * sqrt(window length / bin length): the standard error scaled to one bin.
    double sv = 0.0;
    int k = 0;
    for (const PlateauInput& p : run.plateaus) {
        const double window_s = (p.end_utime - p.start_utime) * 1e-6;
        if (!(p.gyro_sem_v > 0.0) || !(window_s > 0.0)) continue;
        const double v = p.gyro_sem_v * std::sqrt(window_s / bin_s);
        sv += v * v;
        ++k;
    }
    if (k > 0) {
        f.offset_rms_v = std::sqrt(sv / k);
        f.from_standard_errors = true;
        f.dof = k;
    }
    return f;
}

}  // namespace gyrocal::analysis
