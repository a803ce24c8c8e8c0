#include "processors/plateau/plateau_detector.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "lcmtypes/text/names.hpp"
#include "lcmtypes/text/number.hpp"

namespace gyrocal::plateau {

namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

bool InRange(double v, double lo, double hi) { return std::isfinite(v) && v >= lo && v <= hi; }
}  // namespace

std::string PlateauConfig::Validate() const {
    if (!InRange(window_s, 1, 3600)) return "window_s must be in [1, 3600] s";
    if (!InRange(slope_max_c_per_min, 1e-6, 100))
        return "slope_max_c_per_min must be in [1e-6, 100] degC/min";
    if (!InRange(scatter_max_c, 1e-6, 100)) return "scatter_max_c must be in [1e-6, 100] degC";
    if (!InRange(min_stable_s, 0, 36000)) return "min_stable_s must be in [0, 36000] s";
    if (!InRange(average_s, 0.1, 36000)) return "average_s must be in [0.1, 36000] s";
    if (sem_batches < 4 || sem_batches > 1000) return "sem_batches must be in [4, 1000]";
    if (!InRange(rearm_band_c, 1e-6, 1000)) return "rearm_band_c must be in [1e-6, 1000] degC";
    if (!InRange(min_move_fraction, 0, 1)) return "min_move_fraction must be in [0, 1]";
    if (!InRange(leave_factor, 1, 100)) return "leave_factor must be in [1, 100]";
    if (!InRange(state_period_s, 0, 3600)) return "state_period_s must be in [0, 3600] s";
    return "";
}

namespace {

constexpr text::NameTable<State, 4> kStateNames{{{State::kWaiting, "waiting"},
                                                 {State::kSettling, "settling"},
                                                 {State::kAveraging, "averaging"},
                                                 {State::kDone, "done"}}};

}  // namespace

const char* StateName(State s) { return text::NameOf(kStateNames, s); }

PlateauDetector::PlateauDetector(const PlateauConfig& config)
    : config_(config), window_(config.window_s) {
    if (std::string e = config.Validate(); !e.empty()) throw std::invalid_argument(e);
}

void PlateauDetector::Enter(State s) {
    if (s != state_) state_changed_ = true;
    state_ = s;
}

void PlateauDetector::Rearm(double setpoint_change_c) {
    Enter(State::kWaiting);
    state_changed_ = true;
    window_.Clear();
    stable_since_.reset();
    acc_ = Acc{};
    move_ref_c_.reset();
    move_needed_c_ = 0;
    if (std::isfinite(setpoint_change_c) && setpoint_change_c != 0 &&
        config_.min_move_fraction > 0) {
        move_needed_c_ = config_.min_move_fraction * std::fabs(setpoint_change_c);
        // The reference is the temperature now; before any sample it is set by the first one.
        move_ref_c_ = have_sample_ ? last_.temp_c : kNaN;
    }
}

void PlateauDetector::SetChamberSetpoint(double setpoint_c) {
    const bool same =
        (std::isnan(setpoint_c) && std::isnan(setpoint_c_)) || setpoint_c == setpoint_c_;
    if (same) return;
    const double change = setpoint_c - setpoint_c_;  // NaN when either is unknown
    setpoint_c_ = setpoint_c;
    Rearm(change);
}

void PlateauDetector::OnSetpointEvent(double setpoint_c) {
    double change = kNaN;
    if (std::isfinite(setpoint_c)) {
        change = setpoint_c - setpoint_c_;
        setpoint_c_ = setpoint_c;
    }
    Rearm(change);
}

void PlateauDetector::StartRun(const std::string& run_id) {
    run_id_ = run_id;
    Rearm(kNaN);
}

void PlateauDetector::EndRun() {
    run_id_.clear();
    Rearm(kNaN);
}

bool PlateauDetector::CriterionHolds(const numeric::LineFit& fit, double factor) const {
    if (!fit.ok) return false;
    return std::fabs(fit.slope_per_s * 60.0) <= config_.slope_max_c_per_min * factor &&
           fit.resid_std <= config_.scatter_max_c * factor;
}

void PlateauDetector::Settle(const Sample& s, const numeric::LineFit& fit) {
    if (s.moving) return;  // motion neither breaks nor builds stability
    if (!move_ref_c_ && CriterionHolds(fit, 1.0)) {
        if (!stable_since_) stable_since_ = s.utime;
        if (static_cast<double>(s.utime - *stable_since_) >= config_.min_stable_s * 1e6) {
            Enter(State::kAveraging);
            acc_ = Acc{};
        }
    } else {
        stable_since_.reset();
    }
}

void PlateauDetector::Average(const Sample& s, const Sample& prev, bool had_prev,
                              const numeric::LineFit& fit, Step& step) {
    if (!s.moving && !CriterionHolds(fit, config_.leave_factor)) {
        Enter(State::kSettling);
        stable_since_.reset();
        acc_ = Acc{};
        return;
    }
    step.refused = RefuseHole(s);
    Acc& a = acc_;
    if (a.seen_seq && s.seq > a.prev_seq + 1)
        a.gaps += static_cast<int32_t>(s.seq - a.prev_seq - 1);
    a.prev_seq = s.seq;
    a.seen_seq = true;
    if (s.moving) {
        if (a.any) ++a.excluded;
        return;
    }
    if (!a.any) {
        a.any = true;
        a.start_utime = s.utime;
        a.first_seq = s.seq;
    } else if (had_prev && !prev.moving) {
        a.still_us += s.utime - prev.utime;
    }
    a.end_utime = s.utime;
    a.last_seq = s.seq;
    a.t_s.push_back((s.utime - a.start_utime) * 1e-6);
    a.temp_c.push_back(s.temp_c);
    a.gyro_v.push_back(s.gyro_v);
    a.temp_v.push_back(s.temp_v);
    a.supply_v.push_back(s.supply_v);
    if (static_cast<double>(a.still_us) >= config_.average_s * 1e6) {
        step.plateau = Finish();
        Enter(State::kDone);
    }
}

Step PlateauDetector::Feed(const Sample& s) {
    Step step;
    const Sample prev = last_;
    const bool had_prev = have_sample_;
    last_ = s;
    have_sample_ = true;
    if (!s.moving) window_.Add(s.utime, s.temp_c);
    const numeric::LineFit fit = window_.Fit();

    // Setpoint-change guard: cleared once the temperature has moved far enough.
    if (move_ref_c_) {
        if (std::isnan(*move_ref_c_)) {
            move_ref_c_ = s.temp_c;
        } else if (!s.moving && fit.ok &&
                   std::fabs(fit.value_at_last - *move_ref_c_) >= move_needed_c_) {
            move_ref_c_.reset();
        }
    }

    if (state_ == State::kWaiting && window_.size() >= 10 &&
        window_.span_s() >= 0.95 * config_.window_s) {
        Enter(State::kSettling);
    }

    switch (state_) {
        case State::kWaiting:
            break;
        case State::kSettling:
            Settle(s, fit);
            break;
        case State::kAveraging:
            Average(s, prev, had_prev, fit, step);
            break;
        case State::kDone:
            if (!s.moving && fit.ok &&
                std::fabs(fit.value_at_last - last_plateau_temp_c_) > config_.rearm_band_c) {
                Rearm(kNaN);
            }
            break;
    }

    if (state_changed_ || !have_report_ ||
        static_cast<double>(s.utime - last_report_utime_) >= config_.state_period_s * 1e6) {
        step.state = Report(s.utime, fit);
        state_changed_ = false;
        have_report_ = true;
        last_report_utime_ = s.utime;
    }
    return step;
}

std::optional<std::string> PlateauDetector::RefuseHole(const Sample& s) {
    const Acc& a = acc_;
    if (!a.seen_seq || s.seq <= a.prev_seq + 1) return std::nullopt;
    std::string why = text::Printf(
        "averaging window refused at %.0f%% (%.1f s of %.1f s): %lld samples missing "
        "(sequence gap after seq %lld); averaging again from seq %lld",
        100.0 * std::min(1.0, a.still_us * 1e-6 / config_.average_s), a.still_us * 1e-6,
        config_.average_s, static_cast<long long>(s.seq - a.prev_seq - 1),
        static_cast<long long>(a.prev_seq), static_cast<long long>(s.seq));
    acc_ = Acc{};
    return why;
}

Plateau PlateauDetector::Finish() {
    const Acc& a = acc_;
    Plateau p;
    p.run_id = run_id_;
    p.plateau_id = a.start_utime;
    p.setpoint_c = setpoint_c_;
    p.start_utime = a.start_utime;
    p.end_utime = a.end_utime;
    p.first_seq = a.first_seq;
    p.last_seq = a.last_seq;
    p.n_samples = static_cast<int32_t>(a.temp_c.size());
    p.n_excluded_motion = a.excluded;
    p.seq_gaps = a.gaps;
    p.temp_c = numeric::DescribeSeries(a.temp_c, config_.sem_batches);
    p.gyro_v = numeric::DescribeSeries(a.gyro_v, config_.sem_batches);
    const numeric::LineFit line = numeric::FitLine(a.t_s, a.temp_c);
    p.temp_slope_c_per_min = line.ok ? line.slope_per_s * 60.0 : kNaN;
    p.temp_mean_v = numeric::DescribeSeries(a.temp_v, 4).mean;
    double sum = 0;
    int n = 0;
    for (double v : a.supply_v) {
        if (std::isfinite(v)) {
            sum += v;
            ++n;
        }
    }
    p.supply_mean_v = n > 0 ? sum / n : kNaN;
    last_plateau_id_ = p.plateau_id;
    last_plateau_temp_c_ = p.temp_c.mean;
    return p;
}

StateReport PlateauDetector::Report(int64_t utime, const numeric::LineFit& fit) const {
    StateReport r;
    r.utime = utime;
    r.state = state_;
    r.temp_c = last_.temp_c;
    if (fit.ok) {
        r.temp_slope_c_per_min = fit.slope_per_s * 60.0;
        r.temp_std_c = fit.resid_std;
    }
    if (stable_since_ && (state_ == State::kSettling || state_ == State::kAveraging))
        r.stable_for_s = (utime - *stable_since_) * 1e-6;
    if (state_ == State::kAveraging)
        r.averaging_progress = std::min(1.0, acc_.still_us * 1e-6 / config_.average_s);
    if (state_ == State::kDone) r.averaging_progress = 1.0;
    r.last_plateau_id = last_plateau_id_;
    return r;
}

}  // namespace gyrocal::plateau
