#include "processors/rotation/rotation_estimator.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "lcmtypes/text/number.hpp"
#include "processors/numeric/series_stats.hpp"
#include "processors/rotation/slip_check.hpp"

namespace gyrocal::rotation {

namespace {

bool InRange(double v, double lo, double hi) { return std::isfinite(v) && v >= lo && v <= hi; }

int64_t Us(double s) { return static_cast<int64_t>(std::llround(s * 1e6)); }

struct WindowMean {
    double mean = 0, se = 0, t_mean_s = 0, span_s = 0;
    int n = 0;
};

}  // namespace

std::string RotationConfig::Validate() const {
    if (!InRange(guard_s, 0, 60)) return "guard_s must be in [0, 60] s";
    if (!InRange(rest_s, 0.05, 600)) return "rest_s must be in [0.05, 600] s";
    if (!InRange(min_rest_fraction, 0.1, 1)) return "min_rest_fraction must be in [0.1, 1]";
    if (!InRange(min_angle_deg, 0, 3600)) return "min_angle_deg must be in [0, 3600] deg";
    if (!InRange(max_move_s, 0.1, 3600)) return "max_move_s must be in [0.1, 3600] s";
    if (!InRange(encoder_stale_s, 0.01, 600)) return "encoder_stale_s must be in [0.01, 600] s";
    if (!(slip_alpha > 0 && slip_alpha < 0.1)) return "slip_alpha must be in (0, 0.1)";
    if (!InRange(min_slip_deg, 0, 90)) return "min_slip_deg must be in [0, 90] deg";
    return "";
}

RotationEstimator::RotationEstimator(const RotationConfig& config)
    : config_(config), guard_us_(Us(config.guard_s)), rest_us_(Us(config.rest_s)) {
    if (std::string e = config.Validate(); !e.empty()) throw std::invalid_argument(e);
}

void RotationEstimator::AddMove(const motion::TableMove& move) {
    Pending p{move, last_b_utime_.value_or(std::numeric_limits<int64_t>::min())};
    pending_.push_back(p);
    last_b_utime_ = move.end_utime + guard_us_;
}

void RotationEstimator::AddSample(const Sample& s) {
    samples_.push_back(s);
    Prune();
}

void RotationEstimator::AddEncoder(const motion::EncoderReading& reading) {
    encoder_.push_back(reading);
    Prune();
}

void RotationEstimator::Prune() {
    if (samples_.empty()) return;
    int64_t keep_from;
    if (!pending_.empty()) {
        keep_from = pending_.front().move.start_utime - guard_us_ - rest_us_;
    } else {
        const int64_t retention = Us(config_.max_move_s + 5.0) + 2 * guard_us_ + 2 * rest_us_;
        keep_from = samples_.back().utime - retention;
    }
    while (!samples_.empty() && samples_.front().utime < keep_from) samples_.pop_front();
    while (encoder_.size() > 1 && encoder_[1].utime < keep_from) encoder_.pop_front();
}

std::vector<Point> RotationEstimator::Poll(const MotionView& motion) {
    std::vector<Point> out;
    while (!pending_.empty() && !samples_.empty()) {
        const Pending& p = pending_.front();
        const int64_t b = p.move.end_utime + guard_us_;
        int64_t post_end = b + rest_us_;
        std::optional<int64_t> next_a;
        if (pending_.size() > 1) {
            next_a = pending_[1].move.start_utime - guard_us_;
        } else if (motion.current_start_utime) {
            next_a = *motion.current_start_utime - guard_us_;
        }
        const int64_t newest = samples_.back().utime;
        bool ready;
        if (next_a && *next_a <= post_end) {
            post_end = std::max(b, *next_a);
            ready = newest >= post_end;
        } else {
            const bool encoder_past =
                motion.watermark_utime && *motion.watermark_utime >= post_end + guard_us_;
            ready = newest >= post_end &&
                    (encoder_past || newest >= post_end + Us(config_.encoder_stale_s));
        }
        if (!ready) break;
        out.push_back(Compute(p, post_end));
        pending_.pop_front();
    }
    Prune();
    return out;
}

namespace {

// The retained samples split into the rest window before the move [pre_start, a), the move
// [a, b] and the rest window after it (b, post_end].
struct Windows {
    std::vector<const Sample*> pre, mid, post;
};

Windows SplitWindows(const std::deque<Sample>& samples, int64_t pre_start, int64_t a, int64_t b,
                     int64_t post_end) {
    Windows w;
    for (const Sample& s : samples) {
        if (s.utime >= pre_start && s.utime < a)
            w.pre.push_back(&s);
        else if (s.utime >= a && s.utime <= b)
            w.mid.push_back(&s);
        else if (s.utime > b && s.utime <= post_end)
            w.post.push_back(&s);
    }
    return w;
}

// Samples missing (sequence gaps) anywhere from the first rest sample to the last.
int64_t MissingSamples(const std::deque<Sample>& samples, int64_t pre_start, int64_t post_end) {
    int64_t missing = 0;
    const Sample* prev = nullptr;
    for (const Sample& s : samples) {
        if (s.utime < pre_start || s.utime > post_end) continue;
        if (prev && s.seq > prev->seq + 1) missing += s.seq - prev->seq - 1;
        prev = &s;
    }
    return missing;
}

std::vector<double> Values(const std::vector<const Sample*>& w) {
    std::vector<double> v;
    v.reserve(w.size());
    for (const Sample* s : w) v.push_back(s->gyro_v);
    return v;
}

// Mean, mean time and span of a rest window (its standard error is set from the pooled noise).
WindowMean Describe(const std::vector<const Sample*>& w) {
    WindowMean r;
    r.n = static_cast<int>(w.size());
    if (r.n == 0) return r;
    double ts = 0, sum = 0;
    for (const Sample* s : w) {
        ts += (s->utime - w.front()->utime) * 1e-6;
        sum += s->gyro_v;
    }
    r.mean = sum / r.n;
    r.t_mean_s = w.front()->utime * 1e-6 + ts / r.n;
    r.span_s = (w.back()->utime - w.front()->utime) * 1e-6;
    return r;
}

// "" when both rest windows and the move have enough samples, else why not.
std::string WindowsProblem(const WindowMean& w1, const WindowMean& w2, size_t n_move,
                           double need_s) {
    if (w1.n < 4 || w1.span_s < need_s)
        return text::Printf("rest window before the move covers %.3f s, less than %.3f s",
                            w1.span_s, need_s);
    if (w2.n < 4 || w2.span_s < need_s)
        return text::Printf("rest window after the move covers %.3f s, less than %.3f s", w2.span_s,
                            need_s);
    if (n_move < 2) return "fewer than 2 samples inside the move";
    return "";
}

// The offset during the move: the line through the two rest means.
struct OffsetLine {
    WindowMean w1, w2;
    double At(double t_s) const {
        return w1.mean + (w2.mean - w1.mean) * (t_s - w1.t_mean_s) / (w2.t_mean_s - w1.t_mean_s);
    }
};

// [V s] the integral of (v - offset) over the move, trapezoid rule.
double IntegralAboveOffset(const std::vector<const Sample*>& mid, const OffsetLine& offset) {
    double integral = 0;
    for (size_t i = 1; i < mid.size(); ++i) {
        const double ta = mid[i - 1]->utime * 1e-6, tb = mid[i]->utime * 1e-6;
        integral += 0.5 * (tb - ta) *
                    ((mid[i - 1]->gyro_v - offset.At(ta)) + (mid[i]->gyro_v - offset.At(tb)));
    }
    return integral;
}

// A point's identity, angle and mean temperature over the move (accepted or not, it is published).
Point PointOfMove(const motion::TableMove& m, int64_t a, int64_t b,
                  const std::vector<const Sample*>& mid) {
    Point pt;
    pt.rotation_id = a;
    pt.start_utime = a;
    pt.end_utime = b;
    pt.encoder_angle_deg = m.angle_deg();
    pt.direction = pt.encoder_angle_deg >= 0 ? 1 : -1;
    if (!mid.empty()) {
        pt.first_seq = mid.front()->seq;
        pt.last_seq = mid.back()->seq;
        pt.n_samples = static_cast<int32_t>(mid.size());
        double t = 0;
        for (const Sample* s : mid) t += s->temp_c;
        pt.temp_c = t / mid.size();
    }
    return pt;
}

// "" when the move itself may give a point: large enough, short enough, no sample missing.
std::string MoveProblem(const motion::TableMove& m, int64_t missing_samples,
                        const RotationConfig& config) {
    const double angle_deg = m.angle_deg();
    if (std::fabs(angle_deg) < config.min_angle_deg)
        return text::Printf("move of %.3f deg is below the minimum angle %.3f deg", angle_deg,
                            config.min_angle_deg);
    if (static_cast<double>(m.end_utime - m.start_utime) > config.max_move_s * 1e6)
        return text::Printf("move lasted %.1f s, more than the maximum %.1f s",
                            (m.end_utime - m.start_utime) * 1e-6, config.max_move_s);
    if (missing_samples > 0)
        return std::to_string(missing_samples) +
               " samples missing (sequence gaps) inside the move or its rest windows";
    return "";
}

// The encoder against the integrated gyro during the move (slip_check.hpp): "" when they agree.
std::string SlipProblem(const std::deque<motion::EncoderReading>& encoder,
                        const motion::TableMove& m, int64_t a, int64_t b,
                        const std::vector<const Sample*>& mid, const OffsetLine& offset,
                        const Point& pt, double q_v2_s, const RotationConfig& config) {
    SlipInputs si;
    for (const Sample* s : mid) {
        si.gyro_t_s.push_back(s->utime * 1e-6);
        si.gyro_rate_v.push_back(s->gyro_v - offset.At(s->utime * 1e-6));
    }
    for (const motion::EncoderReading& r : encoder) {
        if (r.utime < a || r.utime > b) continue;
        si.encoder_t_s.push_back(r.utime * 1e-6);
        si.encoder_deg.push_back(static_cast<double>(r.counts - m.start_counts) * m.count_deg());
    }
    si.sensitivity_v_per_dps = pt.sensitivity_v_per_dps;
    si.noise_q_v2_s = q_v2_s;
    si.offset_stderr_v = pt.offset_stderr_v;
    si.count_deg = m.count_deg();
    const SlipResult slip = CheckSlip(si, config.slip_alpha, config.min_slip_deg);
    return slip.slip ? slip.reason : "";
}

}  // namespace

Point RotationEstimator::Compute(const Pending& p, int64_t post_end) const {
    const motion::TableMove& m = p.move;
    const int64_t a = m.start_utime - guard_us_;
    const int64_t b = m.end_utime + guard_us_;
    const int64_t pre_start = std::max(a - rest_us_, p.pre_limit_utime);
    const Windows w = SplitWindows(samples_, pre_start, a, b, post_end);
    Point pt = PointOfMove(m, a, b, w.mid);
    auto reject = [&pt](std::string why) {
        pt.accepted = false;
        pt.reject_reason = std::move(why);
        return pt;
    };
    if (std::string why = MoveProblem(m, MissingSamples(samples_, pre_start, post_end), config_);
        !why.empty())
        return reject(why);

    // Rest means, and the noise level pooled over both rest windows (same sensor, seconds
    // apart): variance about each window's line and the integrated autocorrelation time.
    OffsetLine offset{Describe(w.pre), Describe(w.post)};
    WindowMean& w1 = offset.w1;
    WindowMean& w2 = offset.w2;
    const double need_s = config_.min_rest_fraction * config_.rest_s;
    if (std::string why = WindowsProblem(w1, w2, w.mid.size(), need_s); !why.empty())
        return reject(why);
    const numeric::NoiseLevel noise = numeric::PooledNoiseLevel({Values(w.pre), Values(w.post)});
    const double var_eff = noise.var * noise.tau_int;  // [V^2] per sample, correlation included
    w1.se = std::sqrt(var_eff / w1.n);
    w2.se = std::sqrt(var_eff / w2.n);
    const double dt_s = (w1.span_s + w2.span_s) / (w1.n + w2.n - 2);  // mean sample interval

    // Offset line through the two rest means; integrate (v - offset) with the trapezoid rule.
    const double t1 = w1.t_mean_s, t2 = w2.t_mean_s;
    const double integral = IntegralAboveOffset(w.mid, offset);
    const double t_first = w.mid.front()->utime * 1e-6, t_last = w.mid.back()->utime * 1e-6;
    const double t_int = t_last - t_first;
    const double tc = 0.5 * (t_first + t_last);
    const double wb = (tc - t1) / (t2 - t1), wa = 1.0 - wb;
    pt.offset_v = offset.At(tc);
    pt.offset_stderr_v = std::sqrt(wa * wa * w1.se * w1.se + wb * wb * w2.se * w2.se);
    pt.integral_v_s = integral;

    const double q = var_eff * dt_s;  // [V^2 s] two-sided spectral level of the noise
    const double var_i = t_int * t_int * pt.offset_stderr_v * pt.offset_stderr_v + q * t_int;
    const double theta = pt.encoder_angle_deg;
    const double var_theta = 2.0 * m.count_deg() * m.count_deg() / 12.0;
    const double sens = integral / theta;
    pt.sensitivity_v_per_dps = sens;
    pt.sensitivity_stderr_v_per_dps =
        std::sqrt(var_i / (theta * theta) + sens * sens * var_theta / (theta * theta));
    if (!std::isfinite(pt.sensitivity_v_per_dps) ||
        !std::isfinite(pt.sensitivity_stderr_v_per_dps) || !std::isfinite(pt.offset_v) ||
        !std::isfinite(pt.temp_c))
        return reject("a result is not finite (non-finite input?)");
    if (!encoder_.empty()) {
        if (std::string why = SlipProblem(encoder_, m, a, b, w.mid, offset, pt, q, config_);
            !why.empty())
            return reject(why);
    }
    pt.accepted = true;
    return pt;
}

}  // namespace gyrocal::rotation
