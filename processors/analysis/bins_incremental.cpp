#include "processors/analysis/bins_incremental.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "lcmtypes/text/number.hpp"
#include "processors/analysis/steps.hpp"
#include "processors/model/terms.hpp"

namespace gyrocal::analysis {

namespace {

constexpr size_t kChunkCells = 256;  // closed cells per shared chunk

// The parameter a registry term name carries (dTdt(tau), heating(w)); 0 when none.
double ParamOf(const std::string& term) {
    const model::ResolvedTerm t = model::ResolveTerms({term}).front();
    return t.c.param;
}

void InsertSorted(std::vector<double>& v, double x) {
    if (std::find(v.begin(), v.end(), x) != v.end()) return;
    v.insert(std::upper_bound(v.begin(), v.end(), x), x);
}

}  // namespace

TrackerGrid TrackerGrid::For(const AnalysisOptions& o, double width_ratio) {
    if (!(width_ratio > 1.0 && width_ratio <= 2.0))
        throw std::invalid_argument("width_ratio " + text::Sig(width_ratio, 4) +
                                    ": valid is (1, 2]");
    TrackerGrid g;
    // The analysis' dT/dt grid, as candidates.cpp builds it (6 points, log-spaced) and the term
    // names round it: the tracker runs with the parameter the name carries.
    const int n_tau = 6;
    for (int k = 0; k < n_tau; ++k) {
        const double tau =
            o.rate_tau_min_s * std::pow(o.rate_tau_max_s / o.rate_tau_min_s, k / double(n_tau - 1));
        const double named = ParamOf(model::RateTerm(tau));
        InsertSorted(g.rate_taus_s, named);
        // The neighbours the added term's standard error evaluates it at (steps.hpp).
        for (double f : {1.0 - detail::kParamStepRel, 1.0 + detail::kParamStepRel})
            InsertSorted(g.rate_taus_s, ParamOf(model::RateTerm(named * f)));
    }
    InsertSorted(g.rate_taus_s, GYROCAL_DEFAULT_RATE_TAU_S);
    // The searched widths and their neighbours at (1 -+ kParamStepRel) of the range's ends.
    const double lo = o.branch_width_min_c * (1.0 - detail::kParamStepRel),
                 hi = o.branch_width_max_c * (1.0 + detail::kParamStepRel);
    const int n_w =
        std::max(1, static_cast<int>(std::ceil(std::log(hi / lo) / std::log(width_ratio))));
    for (int k = 0; k <= n_w; ++k) g.widths_c.push_back(lo * std::pow(hi / lo, k / double(n_w)));
    // Parameters the declared model names are tracked exactly too.
    for (const model::ResolvedTerm& t : model::ResolveTerms(o.offset_terms)) {
        if ((t.c.kind == GYROCAL_TERM_DTDT || t.c.kind == GYROCAL_TERM_DT_DTDT) && t.c.param > 0.0)
            InsertSorted(g.rate_taus_s, t.c.param);
        if (t.c.kind == GYROCAL_TERM_BRANCH) InsertSorted(g.widths_c, t.c.param);
    }
    return g;
}

IncrementalOptions IncrementalOptions::For(const AnalysisOptions& analysis, double width_ratio) {
    IncrementalOptions o;
    o.bins = analysis.bins;
    o.width_ratio = width_ratio;
    o.grid = TrackerGrid::For(analysis, width_ratio);
    return o;
}

std::string IncrementalOptions::Validate() const {
    if (!(bins.bin_s > 0.0 && bins.bin_s <= 600.0)) return "bin_s must be in (0, 600] s";
    if (!(bins.min_fill > 0.0 && bins.min_fill <= 1.0)) return "min_fill must be in (0, 1]";
    if (!(build.guard_s >= 0.0 && build.guard_s <= 60.0)) return "guard_s must be in [0, 60] s";
    if (const std::string m = build.move.Validate(); !m.empty()) return "move: " + m;
    if (!(width_ratio > 1.0 && width_ratio <= 2.0)) return "width_ratio must be in (1, 2]";
    if (grid.rate_taus_s.empty() || grid.widths_c.empty() ||
        !std::is_sorted(grid.rate_taus_s.begin(), grid.rate_taus_s.end()) ||
        !std::is_sorted(grid.widths_c.begin(), grid.widths_c.end()) ||
        !(grid.rate_taus_s.front() > 0.0 && grid.widths_c.front() > 0.0))
        return "grid: time constants and widths must be positive and ascending";
    if (!(encoder_wait_s >= 0.0 && encoder_wait_s <= 3600.0))
        return "encoder_wait_s must be in [0, 3600] s";
    if (!(air_wait_s >= 0.0 && air_wait_s <= 3600.0)) return "air_wait_s must be in [0, 3600] s";
    if (!(max_cells == 0 || max_cells >= 64))
        return "max_cells must be 0 (no limit) or at least 64";
    return "";
}

// ---- RunMotion ----------------------------------------------------------------------------

RunMotion::RunMotion(const BuildOptions& options) : detector_(options.move) {}

void RunMotion::Add(const motion::EncoderReading& e) {
    ++readings_;
    if (!have_first_) {
        have_first_ = true;
        if (e.counts_per_rev > 0) initial_counts_ = e.counts, counts_per_rev_ = e.counts_per_rev;
    }
    if (e.utime <= last_utime_ || e.counts_per_rev <= 0) {  // as MovesFromEncoder
        ++bad_readings_;
        return;
    }
    last_utime_ = e.utime;
    if (auto m = detector_.Feed({e.utime, e.counts, e.counts_per_rev})) moves_.push_back(*m);
}

std::vector<motion::TableMove> RunMotion::Moves() const {
    std::vector<motion::TableMove> all = moves_;
    if (const auto m = detector_.MoveUnderWay(last_utime_)) all.push_back(*m);
    return all;
}

// ---- UnitBinner ---------------------------------------------------------------------------

UnitBinner::UnitBinner(std::string sensor_id, const IncrementalOptions& options,
                       std::shared_ptr<const TrackerGrid> grid)
    : sensor_id_(std::move(sensor_id)), options_(options), grid_(std::move(grid)) {
    bin_us_ = static_cast<int64_t>(std::llround(options_.bins.bin_s * 1e6));
    guard_us_ = static_cast<int64_t>(options_.build.guard_s * 1e6);  // as BuildSensorRun
    for (size_t j = 0; j < grid_->rate_taus_s.size(); ++j) {
        gyrocal_tracker_config_t c = gyrocal_tracker_config_default();
        c.rate_tau_s = grid_->rate_taus_s[j];
        gyrocal_tracker_t t;
        gyrocal_tracker_init(&t, c);
        rate_trackers_.push_back(t);
        if (c.rate_tau_s == GYROCAL_DEFAULT_RATE_TAU_S) default_tau_ = j;
    }
    memory_c_.assign(grid_->widths_c.size(), 0.0);
    for (double w : grid_->widths_c) half_c_.push_back(0.5 * w);
}

std::optional<int64_t> UnitBinner::first_utime() const {
    if (n_clean_ == 0) return std::nullopt;
    return origin_;
}

void UnitBinner::Track(const GyroSample& s, Open& cell) {
    // dT/dt per time constant and the default branch: the model path's own tracker, so the bin
    // means are those BinnedRun computes from the same samples, bit for bit.
    for (size_t j = 0; j < rate_trackers_.size(); ++j) {
        gyrocal_inputs_t in;
        gyrocal_tracker_update(&rate_trackers_[j], s.utime, s.temp_c, s.supply_v, &in);
        cell.rate_sums[j] += in.dtemp_dt_c_per_s;
        if (j == default_tau_) {
            cell.sums.sum_branch1 += in.branch;
            cell.sums.sum_heating1 += in.heating;
        }
    }
    // The play operator of gyrocal_tracker_update, for every grid width.
    const double t = s.temp_c;
    if (!started_) {
        std::fill(memory_c_.begin(), memory_c_.end(), t);
        started_ = true;
    } else {
        // The memory clamped into [t - half, t + half]: the two ifs of the play operator, written
        // as min/max so that the loop vectorises (a day of 16 units runs it 137M x ~150 times).
        double* m = memory_c_.data();
        const double* h = half_c_.data();
        for (size_t j = 0; j < memory_c_.size(); ++j)
            m[j] = std::min(std::max(m[j], t - h[j]), t + h[j]);
    }
    for (size_t j = 0; j < memory_c_.size(); ++j) cell.lead_sums[j] += t - memory_c_[j];
    incremental::CellSums& a = cell.sums;
    ++a.n;
    a.sum_utime += static_cast<double>(s.utime);
    a.sum_rel_us += s.utime - origin_;
    a.sum_temp += s.temp_c;
    a.sum_gyro += s.gyro_v;
    if (std::isfinite(s.supply_v)) ++a.n_supply, a.sum_supply += s.supply_v;
    cell.utimes.push_back(s.utime);
}

void UnitBinner::AddGyro(const GyroSample& s, const RunMotion& motion) {
    ++n_raw_;
    if (have_seq_ && s.seq > last_seq_ + 1) n_gaps_ += s.seq - last_seq_ - 1;
    if (!have_seq_ || s.seq > last_seq_) last_seq_ = s.seq;
    have_seq_ = true;
    if (!std::isfinite(s.temp_c) || !std::isfinite(s.gyro_v) || s.utime <= last_utime_) {
        ++n_bad_;
        return;
    }
    if (n_clean_ == 0) {
        origin_ = s.utime;
    } else {
        ++spacing_us_[s.utime - last_utime_];
    }
    last_utime_ = s.utime;
    ++n_clean_;
    const int64_t cell = (s.utime - origin_) / bin_us_;
    if (open_.empty() || open_.back().sums.cell != cell) {
        Open o;
        o.sums.cell = cell;
        o.rate_sums.assign(rate_trackers_.size(), 0.0);
        o.lead_sums.assign(memory_c_.size(), 0.0);
        open_.push_back(std::move(o));
    }
    Track(s, open_.back());
    Settle(motion);
}

void UnitBinner::Settle(const RunMotion& motion, bool flush) {
    // The back cell is still being filled until a sample of a later cell (or the end) comes.
    while (open_.size() > (flush ? 0u : 1u)) {
        if (!Decide(open_.front(), motion, flush)) break;
        open_.pop_front();
    }
    ResolveAir(flush);
}

bool UnitBinner::Decide(Open& c, const RunMotion& motion, bool force) {
    const int64_t first = c.utimes.front(), last = c.utimes.back();
    const auto mark = motion.watermark_utime();
    // No move found later can start before the newest reading (a move starts at the last reading
    // at rest), so none can reach back within a guard of a sample earlier than mark - guard.
    const bool stale =
        last_utime_ >= last + guard_us_ + static_cast<int64_t>(options_.encoder_wait_s * 1e6);
    const bool known = force || stale;
    if (!(mark && *mark > last + guard_us_) && !known) return false;
    const std::vector<motion::TableMove>& done = motion.completed();
    size_t m0 = done.size();  // the moves that can reach the cell (in time order)
    while (m0 > 0 && done[m0 - 1].end_utime + guard_us_ >= first) --m0;
    const auto under_way = motion.current_start_utime();
    int64_t moving = 0;
    for (int64_t t : c.utimes) {
        bool near = false;
        for (size_t m = m0; m < done.size() && !near; ++m) near = done[m].Near(t, guard_us_);
        if (!near && under_way && t >= *under_way - guard_us_) {
            // Its end is not known yet: a sample past start + guard waits for it, unless the
            // readings are over (then the move lasts to the newest one, as BuildSensorRun has it).
            if (t <= *under_way + guard_us_ || (known && t <= *mark + guard_us_)) {
                near = true;
            } else if (!known) {
                return false;
            }
        }
        if (near) ++moving;
    }
    if (moving > 0) {
        n_moving_ += moving;
        return true;  // a cell with a move inside is not still data
    }
    Close(c);
    return true;
}

void UnitBinner::Close(Open& c) {
    c.utimes = {};  // what the move decision needed
    awaiting_air_.push_back(std::move(c));
}

void UnitBinner::AddAir(const AirSample& a) {
    if (!std::isfinite(a.air_c) || a.utime <= newest_air_utime_) {
        ++n_bad_air_;
        return;
    }
    newest_air_utime_ = a.utime;
    any_air_ = true;
    air_.push_back(a);
    ResolveAir(false);
}

std::optional<double> incremental::AirFrom(const std::deque<AirSample>& air, double t,
                                           double tolerance_us, bool complete) {
    const AirSample* before = nullptr;
    const AirSample* after = nullptr;
    for (const AirSample& a : air) {
        if (static_cast<double>(a.utime) <= t) {
            before = &a;
        } else {
            after = &a;
            break;
        }
    }
    if (!after && !complete) return std::nullopt;
    return AirBetween(before, after, t, tolerance_us);
}

void UnitBinner::ResolveAir(bool force) {
    const auto wait_us = static_cast<int64_t>(options_.air_wait_s * 1e6);
    while (!awaiting_air_.empty()) {
        Open& c = awaiting_air_.front();
        const double mid = c.sums.sum_utime / c.sums.n;
        // Readings before the last one at or before mid are no longer needed.
        while (air_.size() >= 2 && static_cast<double>(air_[1].utime) <= mid) air_.pop_front();
        const bool complete = force || static_cast<double>(last_utime_) >= mid + wait_us;
        const std::optional<double> air =
            incremental::AirFrom(air_, mid, static_cast<double>(bin_us_), complete);
        if (!air) return;
        c.sums.air_c = *air;
        std::vector<float> lead(c.lead_sums.size());
        for (size_t j = 0; j < lead.size(); ++j)
            lead[j] = static_cast<float>(c.lead_sums[j] / c.sums.n);
        Put(c.sums, c.sums.cell >> level_, c.rate_sums.data(), lead.data());
        awaiting_air_.pop_front();
        if (options_.max_cells > 0 && n_closed_ > static_cast<size_t>(options_.max_cells))
            Coarsen();
    }
}

namespace {

// Adds a closed cell to `to` at grid index `target`; merged into its last cell when that has the
// same index (sums add; the lead means and the air weigh by the samples). Returns true when a
// new cell was added.
bool AddCell(incremental::Chunk& to, const incremental::CellSums& s, int64_t target,
             const double* rate, const float* lead, size_t taus, size_t widths) {
    if (to.cells.empty() || to.cells.back().cell != target) {
        to.cells.push_back(s);
        to.cells.back().cell = target;
        to.rate_sums.insert(to.rate_sums.end(), rate, rate + taus);
        to.lead_means.insert(to.lead_means.end(), lead, lead + widths);
        return true;
    }
    incremental::CellSums& a = to.cells.back();
    const double wa = a.n, wb = s.n, w = wa + wb;
    if (std::isfinite(a.air_c) && std::isfinite(s.air_c)) {
        a.air_c = (wa * a.air_c + wb * s.air_c) / w;
    } else if (!std::isfinite(a.air_c)) {
        a.air_c = s.air_c;
    }
    a.n += s.n;
    a.n_supply += s.n_supply;
    a.sum_utime += s.sum_utime;
    a.sum_temp += s.sum_temp;
    a.sum_gyro += s.sum_gyro;
    a.sum_supply += s.sum_supply;
    a.sum_rel_us += s.sum_rel_us;
    a.sum_branch1 += s.sum_branch1;
    a.sum_heating1 += s.sum_heating1;
    const size_t k = to.cells.size() - 1;
    for (size_t j = 0; j < taus; ++j) to.rate_sums[k * taus + j] += rate[j];
    for (size_t j = 0; j < widths; ++j) {
        float& m = to.lead_means[k * widths + j];
        m = static_cast<float>((wa * m + wb * lead[j]) / w);
    }
    return false;
}

}  // namespace

void UnitBinner::Put(const incremental::CellSums& s, int64_t target, const double* rate,
                     const float* lead) {
    if (tail_.cells.size() >= kChunkCells && tail_.cells.back().cell != target) {
        full_.push_back(std::make_shared<const incremental::Chunk>(std::move(tail_)));
        tail_ = incremental::Chunk{};
    }
    if (AddCell(tail_, s, target, rate, lead, rate_trackers_.size(), memory_c_.size())) ++n_closed_;
}

void UnitBinner::Coarsen() {
    // The old chunks stay alive in the snapshots that share them; new ones are built.
    std::vector<std::shared_ptr<const incremental::Chunk>> old = std::move(full_);
    old.push_back(std::make_shared<const incremental::Chunk>(std::move(tail_)));
    full_.clear();
    tail_ = incremental::Chunk{};
    n_closed_ = 0;
    ++level_;
    const size_t taus = rate_trackers_.size(), widths = memory_c_.size();
    for (const auto& c : old)
        for (size_t i = 0; i < c->cells.size(); ++i)
            Put(c->cells[i], c->cells[i].cell >> 1, &c->rate_sums[i * taus],
                &c->lead_means[i * widths]);
}

void UnitBinner::Append(const Open& c, incremental::Chunk& to) const {
    std::vector<float> lead(c.lead_sums.size());
    for (size_t j = 0; j < lead.size(); ++j)
        lead[j] = static_cast<float>(c.lead_sums[j] / c.sums.n);
    AddCell(to, c.sums, c.sums.cell >> level_, c.rate_sums.data(), lead.data(),
            rate_trackers_.size(), memory_c_.size());
}

void UnitBinner::AddPower(const PowerRecord& p) {
    for (const PowerRecord& q : power_)
        if (q.power_on_utime == p.power_on_utime && q.source == p.source) return;
    power_.push_back(p);
}

size_t UnitBinner::MemoryBytes() const {
    size_t b = sizeof(*this);
    auto chunk = [](const incremental::Chunk& c) {
        return c.cells.capacity() * sizeof(incremental::CellSums) +
               c.rate_sums.capacity() * sizeof(double) + c.lead_means.capacity() * sizeof(float);
    };
    for (const auto& c : full_) b += chunk(*c) + sizeof(*c);
    b += chunk(tail_);
    for (const auto* q : {&open_, &awaiting_air_})
        for (const Open& o : *q)
            b += sizeof(Open) + o.utimes.capacity() * sizeof(int64_t) +
                 (o.rate_sums.capacity() + o.lead_sums.capacity()) * sizeof(double);
    b += air_.size() * sizeof(AirSample) + spacing_us_.size() * 48;
    b += memory_c_.capacity() * 2 * sizeof(double) +
         rate_trackers_.capacity() * sizeof(gyrocal_tracker_t);
    b += (power_.size() + plateaus_.size() + sensitivities_.size()) * 96;
    return b;
}

}  // namespace gyrocal::analysis
