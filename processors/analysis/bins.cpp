#include "processors/analysis/bins.hpp"

#include <algorithm>
#include <cmath>

namespace gyrocal::analysis {

double SamplePeriodS(const SensorRun& run) {
    if (run.samples.size() < 2) return run.samples.empty() ? run.sample_period_s : 0.0;
    std::vector<int64_t> d;
    d.reserve(run.samples.size() - 1);
    for (size_t i = 1; i < run.samples.size(); ++i)
        d.push_back(run.samples[i].utime - run.samples[i - 1].utime);
    std::nth_element(d.begin(), d.begin() + static_cast<long>(d.size() / 2), d.end());
    return d[d.size() / 2] * 1e-6;
}

namespace {

struct Acc {
    int64_t cell = -1;
    int n = 0, n_supply = 0, n_moving = 0;
    double sum_temp = 0, sum_gyro = 0, sum_supply = 0, sum_utime = 0;
    std::vector<size_t> members;
};

// Power-on time in force at each sample: the latest record not after it, else the first sample.
class PowerCursor {
public:
    explicit PowerCursor(const SensorRun& run) : run_(run) {}
    // Feeds `tracker` the power-on of a sample at utime (new power cycles as they start).
    void At(int64_t utime, model::InputTracker& tracker) {
        while (next_ < run_.power_on_utimes.size() && run_.power_on_utimes[next_] <= utime)
            tracker.PowerOn(run_.power_on_utimes[next_++]);
    }

private:
    const SensorRun& run_;
    size_t next_ = 0;
};

// Chamber air at time t [us] (see Bin::air_c); `next` is the first reading after the previous
// query (queries in time order).
double AirAt(const std::vector<AirSample>& air, double t, double tolerance_us, size_t& next) {
    while (next < air.size() && static_cast<double>(air[next].utime) <= t) ++next;
    const AirSample* before = next > 0 ? &air[next - 1] : nullptr;
    const AirSample* after = next < air.size() ? &air[next] : nullptr;
    return AirBetween(before, after, t, tolerance_us);
}

}  // namespace

double AirBetween(const AirSample* before, const AirSample* after, double t, double tolerance_us) {
    if (before && after) {
        const double w = (t - static_cast<double>(before->utime)) /
                         static_cast<double>(after->utime - before->utime);
        return before->air_c + w * (after->air_c - before->air_c);
    }
    const AirSample* near = before ? before : after;
    if (near && std::fabs(static_cast<double>(near->utime) - t) <= tolerance_us) return near->air_c;
    return kNan;
}

// The table's state at rest in every bin: the last move that ended before it.
void AddTableState(const SensorRun& run, std::vector<Bin>& bins) {
    if (!run.has_encoder || run.counts_per_rev <= 0) return;
    size_t m = 0;
    for (Bin& b : bins) {
        while (m < run.moves.size() && run.moves[m].end_utime < b.start_utime) ++m;
        const motion::TableMove* last = m > 0 ? &run.moves[m - 1] : nullptr;
        const int64_t cpr =
            last && last->counts_per_rev > 0 ? last->counts_per_rev : run.counts_per_rev;
        const int64_t counts = last ? last->end_counts : run.initial_counts;
        b.table_deg = static_cast<double>(((counts % cpr) + cpr) % cpr) * 360.0 / cpr;
        b.last_turn_dir = 0.0;
        if (!last) continue;
        const double angle = last->counts_per_rev > 0 ? last->angle_deg() : 0.0;
        b.last_turn_dir = angle > 0 ? 1.0 : angle < 0 ? -1.0 : 0.0;
        const double dur_s = (last->end_utime - last->start_utime) * 1e-6;
        if (dur_s > 0) b.last_turn_rate_dps = std::fabs(angle) / dur_s;
    }
}

bool InPlateauWindow(const SensorRun& run, int64_t start_utime, int64_t end_utime) {
    for (const PlateauInput& p : run.plateaus)
        if (start_utime >= p.start_utime && end_utime <= p.end_utime) return true;
    return false;
}

void AddPlateaus(const SensorRun& run, std::vector<Bin>& bins) {
    for (size_t p = 0; p < run.plateaus.size(); ++p)
        for (Bin& b : bins)
            if (b.start_utime >= run.plateaus[p].start_utime &&
                b.end_utime <= run.plateaus[p].end_utime)
                b.plateau = static_cast<int>(p);
}

BinnedRun::BinnedRun(const SensorRun& run, double bin_s, std::vector<Bin> bins,
                     std::shared_ptr<const TrackedInputSource> inputs, BinDrops underfilled,
                     BinDrops unknown_motion)
    : run_(run),
      bin_s_(bin_s),
      bins_(std::move(bins)),
      underfilled_(underfilled),
      unknown_motion_(unknown_motion),
      inputs_(std::move(inputs)) {}

BinnedRun::BinnedRun(const SensorRun& run, const BinOptions& o) : run_(run), bin_s_(o.bin_s) {
    bin_of_sample_.assign(run.samples.size(), -1);
    const double period_s = SamplePeriodS(run);
    if (period_s <= 0.0 || !(o.bin_s > 0.0)) return;
    const auto bin_us = static_cast<int64_t>(std::llround(o.bin_s * 1e6));
    const int64_t origin = run.first_sample_utime;
    CellCloser closer(run, o, period_s);
    Acc a;
    auto flush = [&]() {
        if (a.n == 0 || a.n_moving > 0) return;
        const std::optional<Bin> b = closer.Close(a);
        if (!b) return;
        for (size_t k : a.members) bin_of_sample_[k] = static_cast<int>(bins_.size());
        bins_.push_back(*b);
    };
    for (size_t k = 0; k < run.samples.size(); ++k) {
        const GyroSample& s = run.samples[k];
        const int64_t cell = (s.utime - origin) / bin_us;
        if (cell != a.cell) {
            flush();
            a = Acc{};
            a.cell = cell;
        }
        if (!run.still[k]) {
            ++a.n_moving;  // a bin with a move inside is not still data
            continue;
        }
        ++a.n;
        a.members.push_back(k);
        a.sum_utime += static_cast<double>(s.utime);
        a.sum_temp += s.temp_c;
        a.sum_gyro += s.gyro_v;
        if (std::isfinite(s.supply_v)) ++a.n_supply, a.sum_supply += s.supply_v;
    }
    flush();
    underfilled_ = closer.underfilled;
    unknown_motion_ = closer.unknown_motion;
    // Time since power-on per bin: the tracker's, averaged (power cycles included).
    std::vector<double> since(bins_.size(), 0.0);
    model::InputTracker t;
    PowerCursor power(run);
    for (size_t k = 0; k < run.samples.size(); ++k) {
        power.At(run.samples[k].utime, t);
        const model::ModelInputs in = t.Update(run.samples[k].utime, run.samples[k].temp_c, kNan);
        if (bin_of_sample_[k] >= 0)
            since[static_cast<size_t>(bin_of_sample_[k])] += in.time_since_power_s;
    }
    for (size_t i = 0; i < bins_.size(); ++i) bins_[i].time_since_power_s = since[i] / bins_[i].n;
    size_t next_air = 0;
    for (Bin& b : bins_)
        b.air_c = AirAt(run.air, b.mid_utime, static_cast<double>(bin_us), next_air);
    AddTableState(run, bins_);
    AddPlateaus(run, bins_);
}

const TrackedInputs& BinnedRun::Track(const gyrocal_tracker_config_t& c) const {
    const auto key = std::make_pair(c.rate_tau_s, c.branch_width_c);
    if (auto it = tracked_.find(key); it != tracked_.end()) return it->second;
    if (inputs_) return tracked_.emplace(key, inputs_->Track(c)).first->second;
    TrackedInputs t;
    t.rate.assign(bins_.size(), 0.0);
    t.branch.assign(bins_.size(), 0.0);
    t.heating.assign(bins_.size(), 0.0);
    model::InputTracker tracker(c);
    PowerCursor power(run_);
    for (size_t k = 0; k < run_.samples.size(); ++k) {
        const GyroSample& s = run_.samples[k];
        power.At(s.utime, tracker);
        const model::ModelInputs in = tracker.Update(s.utime, s.temp_c, s.supply_v);
        const int b = bin_of_sample_[k];
        if (b < 0) continue;
        t.rate[static_cast<size_t>(b)] += in.dtemp_dt_c_per_s;
        t.branch[static_cast<size_t>(b)] += in.branch;
        t.heating[static_cast<size_t>(b)] += in.heating;
    }
    for (size_t i = 0; i < bins_.size(); ++i) {
        t.rate[i] /= bins_[i].n;
        t.branch[i] /= bins_[i].n;
        t.heating[i] /= bins_[i].n;
    }
    return tracked_.emplace(key, std::move(t)).first->second;
}

model::ModelInputs BinnedRun::Inputs(size_t i, const gyrocal_tracker_config_t& c) const {
    const TrackedInputs& t = Track(c);
    const Bin& b = bins_[i];
    model::ModelInputs in;
    in.temp_c = b.temp_c;
    in.dtemp_dt_c_per_s = t.rate[i];
    in.rate_tau_s = c.rate_tau_s;
    in.supply_v = b.supply_v;
    in.branch = t.branch[i];
    in.heating = t.heating[i];
    in.branch_width_c = c.branch_width_c;
    in.direction = 0.0;  // at rest: a direction term contributes nothing
    in.time_since_power_s = b.time_since_power_s;
    return in;
}

Eigen::VectorXd BinnedRun::Column(const std::string& term, double t0_c) const {
    model::Model one;
    one.term_names = {term};
    const gyrocal_tracker_config_t c = model::TrackerConfigFor(one);
    const model::ResolvedTerm t = model::ResolveTerms({term}).front();
    Eigen::VectorXd col(static_cast<Eigen::Index>(bins_.size()));
    for (size_t i = 0; i < bins_.size(); ++i) {
        const model::ModelInputs in = Inputs(i, c);
        col[static_cast<Eigen::Index>(i)] = t(in.temp_c - t0_c, in);
    }
    return col;
}

Eigen::MatrixXd BinnedRun::Design(const std::vector<std::string>& terms, double t0_c) const {
    Eigen::MatrixXd x(static_cast<Eigen::Index>(bins_.size()),
                      static_cast<Eigen::Index>(terms.size()));
    for (size_t j = 0; j < terms.size(); ++j)
        x.col(static_cast<Eigen::Index>(j)) = Column(terms[j], t0_c);
    return x;
}

Eigen::VectorXd BinnedRun::Values(const model::Model& m) const {
    const model::Evaluator ev(m);
    const gyrocal_tracker_config_t c = model::TrackerConfigFor(m);
    Eigen::VectorXd v(static_cast<Eigen::Index>(bins_.size()));
    for (size_t i = 0; i < bins_.size(); ++i)
        v[static_cast<Eigen::Index>(i)] = ev.Value(Inputs(i, c), model::RangePolicy::kExtrapolate);
    return v;
}

Floor NoiseFloor(const std::vector<Bin>& bins, const Eigen::VectorXd& values) {
    Floor f;
    double ss = 0.0;
    for (size_t i = 1; i < bins.size(); ++i) {
        if (bins[i].segment != bins[i - 1].segment) continue;
        const double d =
            values[static_cast<Eigen::Index>(i)] - values[static_cast<Eigen::Index>(i - 1)];
        if (!std::isfinite(d)) continue;
        ss += d * d;
        ++f.pairs;
    }
    if (f.pairs > 0) f.offset_rms_v = std::sqrt(ss / (2.0 * f.pairs));
    return f;
}

}  // namespace gyrocal::analysis
