#include "processors/noise/noise_tracker.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "processors/numeric/line_fit.hpp"

namespace gyrocal::noise {

namespace {

bool In(double v, double lo, double hi) { return std::isfinite(v) && v >= lo && v <= hi; }

}  // namespace

std::string TrackerConfig::Validate() const {
    if (!In(bin_s, 0.001, 10)) return "--noise-bin-s must be in [0.001, 10] s";
    if (!In(quiet_slope_c_per_min, 0.001, 10))
        return "--noise-quiet-slope-c-per-min must be in [0.001, 10] degC/min";
    if (!In(slope_window_s, 1, 3600)) return "--noise-slope-window-s must be in [1, 3600] s";
    if (!In(min_segment_s, 4 * bin_s, 86400))
        return "--noise-min-segment-s must be in [4 bins, 86400] s";
    if (!In(min_fit_tau_s, bin_s, 100))
        return "--noise-min-fit-tau-s must be in [--noise-bin-s, 100] s";
    if (!In(max_tau_s, min_fit_tau_s, 1e6))
        return "--noise-max-tau-s must be at least --noise-min-fit-tau-s (and <= 1e6 s)";
    return "";
}

NoiseTracker::NoiseTracker(const TrackerConfig& config) : config_(config) {
    if (std::string e = config.Validate(); !e.empty()) throw std::invalid_argument(e);
}

void NoiseTracker::Reset() {
    closed_.clear();
    bins_.clear();
    in_stretch_ = false;
    bin_n_ = 0;
    bin_sum_ = bin_temp_ = bin_t_ = 0;
}

void NoiseTracker::Add(const motion::GyroSample& s, bool moving) {
    newest_utime_ = s.utime;
    if (moving) {
        CloseStretch();
        return;
    }
    if (in_stretch_) {
        const int64_t dt = s.utime - last_utime_;
        const bool irregular = interval_us_ > 0 && std::abs(dt - interval_us_) * 2 > interval_us_;
        if (s.seq != last_seq_ + 1 || irregular) CloseStretch();
    }
    if (in_stretch_ && interval_us_ == 0) {
        // The first interval of the run fixes the bins: tau0 is the same for every stretch.
        interval_us_ = s.utime - last_utime_;
        per_bin_ = std::max(1, static_cast<int>(std::lround(config_.bin_s * 1e6 / interval_us_)));
        tau0_s_ = per_bin_ * interval_us_ * 1e-6;
        grid_ = TauGrid(static_cast<int64_t>(config_.max_tau_s / tau0_s_));
        max_held_bins_ = static_cast<size_t>(std::ceil(4.0 * config_.max_tau_s / tau0_s_));
    }
    in_stretch_ = true;
    last_utime_ = s.utime;
    last_seq_ = s.seq;
    bin_sum_ += s.gyro_v;
    bin_temp_ += s.temp_c;
    bin_t_ += s.utime * 1e-6;
    ++bin_n_;
    if (per_bin_ > 0 && bin_n_ >= per_bin_) {
        bins_.push_back({bin_t_ / bin_n_, bin_sum_ / bin_n_, bin_temp_ / bin_n_});
        bin_n_ = 0;
        bin_sum_ = bin_temp_ = bin_t_ = 0;
        if (max_held_bins_ > 0 && bins_.size() >= max_held_bins_) {
            // Long enough for every tau of the grid: a segment of its own, the stretch goes on.
            Segment(bins_, closed_);
            bins_.clear();
        }
    }
}

void NoiseTracker::CloseStretch() {
    if (!bins_.empty() && tau0_s_ > 0) Segment(bins_, closed_);
    bins_.clear();
    in_stretch_ = false;
    bin_n_ = 0;
    bin_sum_ = bin_temp_ = bin_t_ = 0;
}

void NoiseTracker::Segment(const std::vector<Bin>& bins, std::vector<SegmentSums>& out) const {
    const size_t n = bins.size();
    const auto min_bins = static_cast<size_t>(std::ceil(config_.min_segment_s / tau0_s_));
    if (n < min_bins || n < 4) return;
    numeric::PrefixLine temp(n);
    for (size_t i = 0; i < n; ++i) temp.Set(i, bins[i].t_s - bins[0].t_s, bins[i].temp_c);
    const auto half = static_cast<size_t>(std::max(1.0, 0.5 * config_.slope_window_s / tau0_s_));
    const auto smooth = static_cast<size_t>(std::max(1.0, 5.0 / tau0_s_));
    size_t a = 0;
    while (a < n) {
        auto quiet = [&](size_t i) {
            const size_t lo = i > half ? i - half : 0, hi = std::min(n, i + half + 1);
            return std::abs(temp.Slope(lo, hi)) * 60.0 <= config_.quiet_slope_c_per_min;
        };
        while (a < n && !quiet(a)) ++a;
        size_t b = a;
        while (b < n && quiet(b)) ++b;
        if (b - a >= min_bins && b - a >= 4) {
            // Regress the values on the smoothed temperature (a line), keep the residual.
            std::vector<double> ts(b - a), y(b - a);
            double mt = 0, my = 0;
            for (size_t i = a; i < b; ++i) {
                const size_t lo = std::max(a, i > smooth ? i - smooth : 0),
                             hi = std::min(b, i + smooth + 1);
                ts[i - a] = temp.Mean(lo, hi);
                y[i - a] = bins[i].value;
                mt += ts[i - a];
                my += y[i - a];
            }
            mt /= static_cast<double>(b - a);
            my /= static_cast<double>(b - a);
            double sxy = 0, sxx = 0;
            for (size_t k = 0; k < ts.size(); ++k) {
                sxy += (ts[k] - mt) * (y[k] - my);
                sxx += (ts[k] - mt) * (ts[k] - mt);
            }
            const double slope = sxx > 1e-12 ? sxy / sxx : 0.0;
            for (size_t k = 0; k < y.size(); ++k) y[k] = y[k] - my - slope * (ts[k] - mt);
            out.push_back(SumSegment(y, tau0_s_, grid_));
        }
        a = b;
    }
}

NoiseEstimate NoiseTracker::Estimate() const {
    NoiseEstimate e;
    e.utime = newest_utime_;
    e.tau0_s = tau0_s_;
    if (tau0_s_ <= 0) {
        e.terms.note = "no still samples yet";
        return e;
    }
    std::vector<SegmentSums> all = closed_;
    if (!bins_.empty()) Segment(bins_, all);
    std::string screened;
    const std::vector<SegmentSums> segments = ScreenSegments(all, tau0_s_, grid_, 0.01, screened);
    for (const SegmentSums& s : segments) {
        e.still_s += s.length_s;
        e.longest_s = std::max(e.longest_s, s.length_s);
    }
    e.segments = static_cast<int>(segments.size());
    e.adev = Combine(segments, tau0_s_, grid_);
    e.terms = FitTerms(segments, tau0_s_, grid_, config_.min_fit_tau_s);
    if (!screened.empty())
        e.terms.note = screened + (e.terms.note.empty() ? "" : "; " + e.terms.note);
    return e;
}

}  // namespace gyrocal::noise
