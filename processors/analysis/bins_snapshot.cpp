// Snapshots of incremental bins and the run binner (bins_incremental.hpp).
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "lcmtypes/text/number.hpp"
#include "processors/analysis/bins_incremental.hpp"

namespace gyrocal::analysis {

namespace {

using incremental::Chunk;

// Where a kept bin's cell is: chunk and index in it.
struct CellAt {
    uint32_t chunk = 0, index = 0;
};

// The tracked inputs of a snapshot's kept bins (see the header for what is exact).
class SnapshotInputs : public TrackedInputSource {
public:
    SnapshotInputs(std::vector<std::shared_ptr<const Chunk>> chunks, std::vector<CellAt> at,
                   std::shared_ptr<const TrackerGrid> grid,
                   std::shared_ptr<std::vector<std::string>> notes)
        : chunks_(std::move(chunks)),
          at_(std::move(at)),
          grid_(std::move(grid)),
          notes_(std::move(notes)) {}

    TrackedInputs Track(const gyrocal_tracker_config_t& c) const override {
        const size_t n = at_.size();
        TrackedInputs t;
        t.rate.assign(n, kNan);
        t.branch.assign(n, kNan);
        t.heating.assign(n, kNan);
        Rate(c.rate_tau_s, t.rate);
        if (c.branch_width_c == GYROCAL_SIGN_BRANCH_WIDTH_C) {
            for (size_t i = 0; i < n; ++i) {
                const incremental::CellSums& s = Cell(i);
                t.branch[i] = s.sum_branch1 / s.n;
                t.heating[i] = s.sum_heating1 / s.n;
            }
        } else {
            Branch(c.branch_width_c, t.branch);  // heating is only defined for the sign width
        }
        return t;
    }

private:
    const incremental::CellSums& Cell(size_t i) const {
        return chunks_[at_[i].chunk]->cells[at_[i].index];
    }
    double RateSum(size_t i, size_t j) const {
        const size_t taus = grid_->rate_taus_s.size();
        return chunks_[at_[i].chunk]->rate_sums[at_[i].index * taus + j];
    }
    double Lead(size_t i, size_t j) const {
        const size_t widths = grid_->widths_c.size();
        return chunks_[at_[i].chunk]->lead_means[at_[i].index * widths + j];
    }
    void Note(const std::string& what) const {
        if (std::find(notes_->begin(), notes_->end(), what) == notes_->end())
            notes_->push_back(what);
    }

    void Rate(double tau, std::vector<double>& out) const {
        const std::vector<double>& g = grid_->rate_taus_s;
        const auto hi = std::lower_bound(g.begin(), g.end(), tau);
        if (hi != g.end() && *hi == tau) {
            const auto j = static_cast<size_t>(hi - g.begin());
            for (size_t i = 0; i < out.size(); ++i) out[i] = RateSum(i, j) / Cell(i).n;
            return;
        }
        if (hi == g.begin() || hi == g.end()) {
            Note("dT/dt time constant " + text::Sig(tau, 4) + " s outside the tracked " +
                 text::Sig(g.front(), 3) + ".." + text::Sig(g.back(), 3) + " s: not available");
            return;
        }
        // Not tracked: interpolated in log tau between its neighbours (no bound: named).
        const size_t b = static_cast<size_t>(hi - g.begin()), a = b - 1;
        const double w = std::log(tau / g[a]) / std::log(g[b] / g[a]);
        Note("dT/dt time constant " + text::Sig(tau, 4) + " s not tracked: interpolated between " +
             text::Sig(g[a], 3) + " and " + text::Sig(g[b], 3) + " s");
        for (size_t i = 0; i < out.size(); ++i)
            out[i] = ((1.0 - w) * RateSum(i, a) + w * RateSum(i, b)) / Cell(i).n;
    }

    void Branch(double width, std::vector<double>& out) const {
        const std::vector<double>& g = grid_->widths_c;
        const double r = 0.5 * width;
        if (!(width >= g.front() * (1 - 1e-12) && width <= g.back() * (1 + 1e-12))) {
            Note("branch width " + text::Sig(width, 4) + " degC outside the tracked " +
                 text::Sig(g.front(), 3) + ".." + text::Sig(g.back(), 3) + " degC: not available");
            return;
        }
        size_t b = static_cast<size_t>(std::lower_bound(g.begin(), g.end(), width) - g.begin());
        b = std::min(std::max<size_t>(b, 1), g.size() - 1);
        const size_t a = b - 1;
        // Linear in the half width between the grid's neighbours: the bin mean of (T - memory) is
        // 1-Lipschitz in it (header), so the error is at most half the step.
        const double ra = 0.5 * g[a], rb = 0.5 * g[b];
        const double w = g.size() == 1 ? 0.0 : std::clamp((r - ra) / (rb - ra), 0.0, 1.0);
        for (size_t i = 0; i < out.size(); ++i)
            out[i] = ((1.0 - w) * Lead(i, a) + w * Lead(i, b)) / r;
    }

    std::vector<std::shared_ptr<const Chunk>> chunks_;
    std::vector<CellAt> at_;
    std::shared_ptr<const TrackerGrid> grid_;
    std::shared_ptr<std::vector<std::string>> notes_;
};

// [s] since the power-on in force at the cell's mean sample time (the latest record not after it,
// else the first sample), from the exact integer sum: the mean of the per-sample differences.
double TimeOn(const SensorRun& run, const incremental::CellSums& c) {
    const int64_t origin = run.first_sample_utime;
    const double mean_rel_us = static_cast<double>(c.sum_rel_us) / c.n;
    int64_t on = origin;
    for (int64_t p : run.power_on_utimes)
        if (static_cast<double>(p - origin) <= mean_rel_us) on = p;
    return 1e-6 * (static_cast<double>(origin - on) + mean_rel_us);
}

}  // namespace

const SensorRun& BinSnapshot::run() const {
    static const SensorRun kNone;
    return run_ ? *run_ : kNone;
}

size_t BinSnapshot::cells() const {
    size_t n = 0;
    for (const auto& c : chunks_) n += c->cells.size();
    return n;
}

std::vector<std::string> BinSnapshot::Approximations() const {
    return approximations_ ? *approximations_ : std::vector<std::string>{};
}

BinnedRun BinSnapshot::Binned(const BinOptions& o) const {
    if (!run_) throw std::logic_error("BinSnapshot::Binned: an empty snapshot (no unit)");
    if (o.bin_s != bin_s_)
        throw std::invalid_argument("bins of " + text::Sig(o.bin_s, 3) + " s asked of cells of " +
                                    text::Sig(bin_s_, 3) + " s");
    std::vector<Bin> bins;
    std::vector<CellAt> at;
    BinDrops underfilled, unknown_motion;
    const double period_s = run_->sample_period_s;
    if (period_s > 0.0) {
        CellCloser closer(*run_, o, period_s);  // as BinnedRun: gaps, partial cells
        for (size_t k = 0; k < chunks_.size(); ++k) {
            for (size_t i = 0; i < chunks_[k]->cells.size(); ++i) {
                const incremental::CellSums& c = chunks_[k]->cells[i];
                std::optional<Bin> b = closer.Close(c);
                if (!b) continue;
                b->time_since_power_s = TimeOn(*run_, c);
                b->air_c = c.air_c;
                bins.push_back(*b);
                at.push_back({static_cast<uint32_t>(k), static_cast<uint32_t>(i)});
            }
        }
        underfilled = closer.underfilled;
        unknown_motion = closer.unknown_motion;
    }
    AddTableState(*run_, bins);
    AddPlateaus(*run_, bins);
    auto inputs = std::make_shared<SnapshotInputs>(chunks_, std::move(at), grid_, approximations_);
    return BinnedRun(*run_, o.bin_s, std::move(bins), std::move(inputs), underfilled,
                     unknown_motion);
}

SensorResult BinSnapshot::Analyze(const AnalysisOptions& options) const {
    const BinnedRun binned = Binned(options.bins);
    SensorResult r = AnalyzeBinned(*run_, binned, options);
    for (const std::string& a : Approximations()) r.notes.push_back("incremental bins: " + a);
    return r;
}

int64_t UnitBinner::MedianSpacingUs() const {
    int64_t total = 0;
    for (const auto& [d, n] : spacing_us_) total += n;
    if (total == 0) return 0;
    const int64_t k = total / 2;  // the element nth_element puts at size / 2 (bins.cpp)
    int64_t seen = 0;
    for (const auto& [d, n] : spacing_us_) {
        seen += n;
        if (seen > k) return d;
    }
    return 0;
}

BinSnapshot UnitBinner::Snapshot(const RunMotion& motion) const {
    BinSnapshot s;
    auto run = std::make_shared<SensorRun>(
        BuildSensorRun(sensor_id_, {}, {}, plateaus_, sensitivities_, power_, options_.build));
    run->moves = motion.Moves();
    run->has_encoder = motion.has_encoder();
    run->n_bad_encoder = motion.bad_readings();
    run->motion_unknown = motion.motion_unknown();
    run->initial_counts = motion.initial_counts();
    run->counts_per_rev = motion.counts_per_rev();
    run->first_sample_utime = origin_;
    run->n_raw_samples = n_raw_;
    run->n_moving_samples = n_moving_;
    run->n_bad_samples = n_bad_;
    run->n_seq_gaps = n_gaps_;
    run->n_bad_air = n_bad_air_;
    run->sample_period_s = 1e-6 * static_cast<double>(MedianSpacingUs());
    s.run_ = std::move(run);
    s.bin_s_ = options_.bins.bin_s * static_cast<double>(int64_t{1} << level_);
    s.grid_ = grid_;
    s.chunks_ = full_;
    // The open tail and the cells still waiting for air (given what is known of it) are copied:
    // at most one chunk and a few cells.
    auto tail = std::make_shared<Chunk>(tail_);
    for (const Open& c : awaiting_air_) {
        Open r = c;
        r.sums.air_c = *incremental::AirFrom(air_, c.sums.sum_utime / c.sums.n,
                                             static_cast<double>(bin_us_), true);
        Append(r, *tail);
    }
    s.chunks_.push_back(std::move(tail));
    s.approximations_ = std::make_shared<std::vector<std::string>>();
    return s;
}

// ---- RunBinner ----------------------------------------------------------------------------

RunBinner::RunBinner(IncrementalOptions options)
    : options_(std::move(options)), motion_(options_.build) {
    if (options_.grid.rate_taus_s.empty() && options_.grid.widths_c.empty())
        options_.grid = TrackerGrid::For(AnalysisOptions::Defaults(), options_.width_ratio);
    if (const std::string p = options_.Validate(); !p.empty())
        throw std::invalid_argument("incremental bins: " + p);
    grid_ = std::make_shared<const TrackerGrid>(options_.grid);
}

UnitBinner& RunBinner::Unit(const std::string& id) {
    auto it = units_.find(id);
    if (it != units_.end()) return it->second;
    it = units_.emplace(id, UnitBinner(id, options_, grid_)).first;
    if (last_air_) it->second.AddAir(*last_air_);
    return it->second;
}

void RunBinner::AddGyro(const std::string& id, const GyroSample& s) {
    Unit(id).AddGyro(s, motion_);
}

void RunBinner::AddEncoder(const motion::EncoderReading& e) {
    motion_.Add(e);
    for (auto& [id, u] : units_) u.Settle(motion_);
}

void RunBinner::AddPower(const std::string& id, const PowerRecord& p) { Unit(id).AddPower(p); }

void RunBinner::AddAir(const AirSample& a) {
    if (std::isfinite(a.air_c) && (!last_air_ || a.utime > last_air_->utime)) last_air_ = a;
    for (auto& [id, u] : units_) u.AddAir(a);
}

void RunBinner::AddPlateau(const std::string& id, const PlateauInput& p) { Unit(id).AddPlateau(p); }

void RunBinner::AddSensitivity(const std::string& id, const SensitivityInput& p) {
    Unit(id).AddSensitivity(p);
}

void RunBinner::Flush() {
    for (auto& [id, u] : units_) u.Settle(motion_, true);
}

void RunBinner::Absorb(RunBinner&& other) {
    for (auto& [id, u] : other.units_)
        if (units_.count(id))
            throw std::invalid_argument("incremental bins: unit " + id + " twice");
    for (auto& [id, u] : other.units_) units_.emplace(id, std::move(u));
    other.units_.clear();
}

BinSnapshot RunBinner::Snapshot(const std::string& id) const {
    return units_.at(id).Snapshot(motion_);
}

std::vector<std::string> RunBinner::sensors() const {
    std::vector<std::string> v;
    for (const auto& [id, u] : units_) v.push_back(id);
    return v;
}

const UnitBinner* RunBinner::unit(const std::string& id) const {
    const auto it = units_.find(id);
    return it == units_.end() ? nullptr : &it->second;
}

size_t RunBinner::MemoryBytes() const {
    size_t b = sizeof(*this) + motion_.completed().capacity() * sizeof(motion::TableMove);
    for (const auto& [id, u] : units_) b += u.MemoryBytes() + id.capacity();
    return b;
}

}  // namespace gyrocal::analysis
