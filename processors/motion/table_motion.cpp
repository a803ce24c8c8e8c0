#include "processors/motion/table_motion.hpp"

#include <cmath>
#include <cstdlib>

namespace gyrocal::motion {

std::string MoveDetectorConfig::Validate() const {
    if (start_threshold_counts < 1) return "start_threshold_counts must be >= 1";
    if (settle_band_counts < 0 || settle_band_counts >= start_threshold_counts + 1)
        return "settle_band_counts must be in [0, start_threshold_counts]";
    if (!std::isfinite(settle_s) || settle_s <= 0 || settle_s > 60)
        return "settle_s must be in (0, 60] s";
    return "";
}

MoveDetector::MoveDetector(const MoveDetectorConfig& config) : config_(config) {}

std::optional<TableMove> MoveDetector::Feed(const EncoderReading& r) {
    if (!have_ || r.counts_per_rev != last_.counts_per_rev) {
        have_ = true;
        moving_ = false;
        rest_counts_ = r.counts;
        last_ = r;
        return std::nullopt;
    }
    std::optional<TableMove> done;
    if (!moving_) {
        if (std::llabs(r.counts - rest_counts_) > config_.start_threshold_counts) {
            moving_ = true;
            current_ = TableMove{};
            current_.start_utime = last_.utime;
            current_.start_counts = rest_counts_;
            current_.counts_per_rev = r.counts_per_rev;
            settle_ref_counts_ = r.counts;
            last_change_utime_ = r.utime;
        }
    } else {
        if (std::llabs(r.counts - settle_ref_counts_) > config_.settle_band_counts) {
            settle_ref_counts_ = r.counts;
            last_change_utime_ = r.utime;
        } else if (static_cast<double>(r.utime - last_change_utime_) >= config_.settle_s * 1e6) {
            // The reading now, not the settle reference: the last counts of a decelerating
            // table come one at a time, inside the band, after the reference was taken.
            current_.end_utime = last_change_utime_;
            current_.end_counts = r.counts;
            moving_ = false;
            rest_counts_ = r.counts;
            done = current_;
        }
    }
    last_ = r;
    return done;
}

std::optional<int64_t> MoveDetector::current_start_utime() const {
    if (!moving_) return std::nullopt;
    return current_.start_utime;
}

std::optional<TableMove> MoveDetector::MoveUnderWay(int64_t last_utime) const {
    if (!moving_) return std::nullopt;
    TableMove m;
    m.start_utime = current_.start_utime;
    m.end_utime = last_utime;
    return m;
}

std::optional<int64_t> MoveDetector::watermark_utime() const {
    if (!have_) return std::nullopt;
    return last_.utime;
}

TableMotion::TableMotion(const MoveDetectorConfig& config, double guard_s, double stale_s)
    : detector_(config),
      guard_us_(static_cast<int64_t>(std::llround(guard_s * 1e6))),
      stale_us_(static_cast<int64_t>(std::llround(stale_s * 1e6))) {}

std::optional<TableMove> TableMotion::Feed(const EncoderReading& reading) {
    auto move = detector_.Feed(reading);
    if (move) moves_.push_back(*move);
    return move;
}

bool TableMotion::Decided(int64_t t, int64_t newest_stream_utime) const {
    const auto mark = detector_.watermark_utime();
    if (mark && *mark >= t + guard_us_) return true;
    return newest_stream_utime >= t + guard_us_ + stale_us_;
}

bool TableMotion::Moving(int64_t t) const {
    if (auto start = detector_.current_start_utime(); start && t >= *start - guard_us_) return true;
    for (const TableMove& m : moves_) {
        if (m.Near(t, guard_us_)) return true;
    }
    return false;
}

void TableMotion::Prune(int64_t t) {
    while (!moves_.empty() && moves_.front().end_utime + guard_us_ < t) moves_.pop_front();
}

}  // namespace gyrocal::motion
