#include "producers/sim/turntable.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace gyrocal::sim {

double TableMove::Duration() const {
    const double d = std::abs(distance_deg);
    if (d * accel_dps2 >= rate_dps * rate_dps) return d / rate_dps + rate_dps / accel_dps2;
    return 2.0 * std::sqrt(d / accel_dps2);  // triangle: peak rate below cruise
}

void TableMove::At(double elapsed_s, double& pos_deg, double& rate) const {
    const double d = std::abs(distance_deg);
    const double sign = distance_deg < 0.0 ? -1.0 : 1.0;
    const double a = accel_dps2;
    const double v = std::min(rate_dps, std::sqrt(d * a));  // peak rate actually reached
    const double t_acc = v / a;
    const double total = Duration();
    const double t = std::clamp(elapsed_s, 0.0, total);
    double p, r;
    if (t < t_acc) {
        p = 0.5 * a * t * t;
        r = a * t;
    } else if (t < total - t_acc) {
        p = 0.5 * a * t_acc * t_acc + v * (t - t_acc);
        r = v;
    } else {
        const double left = total - t;
        p = d - 0.5 * a * left * left;
        r = a * left;
    }
    pos_deg = sign * p;
    rate = sign * r;
}

std::string TurntableModel::Command(int64_t cmd_id, double move_deg, double rate_dps,
                                    double accel_dps2, double now_s) {
    std::ostringstream why;
    why << "turntable cmd_id " << cmd_id << ": ";
    if (!std::isfinite(move_deg) || !std::isfinite(rate_dps) || !std::isfinite(accel_dps2)) {
        why << "move_deg, rate_dps and accel_dps2 must be finite";
        return why.str();
    }
    if (std::abs(move_deg) > config_.max_move_deg) {
        why << "move_deg " << move_deg << " beyond the table's limit of +-" << config_.max_move_deg;
        return why.str();
    }
    if (rate_dps > config_.max_rate_dps) {
        why << "rate_dps " << rate_dps << " above the table's limit of " << config_.max_rate_dps
            << " (<= 0 means the default " << config_.default_rate_dps << ")";
        return why.str();
    }
    if (accel_dps2 > config_.max_accel_dps2) {
        why << "accel_dps2 " << accel_dps2 << " above the table's limit of "
            << config_.max_accel_dps2 << " (<= 0 means the default " << config_.default_accel_dps2
            << ")";
        return why.str();
    }
    if (queue_.size() >= kMaxQueuedMoves) {
        why << "the table already has " << queue_.size() << " moves queued (limit "
            << kMaxQueuedMoves << ")";
        return why.str();
    }
    if (move_deg == 0.0) return "";  // nothing to do; accepted
    TableMove m;
    m.cmd_id = cmd_id;
    m.distance_deg = move_deg;
    m.rate_dps = rate_dps > 0.0 ? rate_dps : config_.default_rate_dps;
    m.accel_dps2 = accel_dps2 > 0.0 ? accel_dps2 : config_.default_accel_dps2;
    m.start_s = queue_.empty() ? now_s : queue_.back().start_s + queue_.back().Duration();
    queue_.push_back(m);
    return "";
}

void TurntableModel::AdvanceTo(double t_s) {
    while (!queue_.empty() && t_s >= queue_.front().start_s + queue_.front().Duration()) {
        base_angle_deg_ += queue_.front().distance_deg;
        queue_.pop_front();
    }
}

void TurntableModel::At(double t_s, double& angle_deg, double& rate) const {
    angle_deg = base_angle_deg_;
    rate = 0.0;
    if (queue_.empty() || t_s < queue_.front().start_s) return;
    double pos = 0.0;
    queue_.front().At(t_s - queue_.front().start_s, pos, rate);
    angle_deg += pos;
}

int64_t EncoderModel::Counts(double angle_deg) const {
    return static_cast<int64_t>(std::floor(angle_deg * counts_per_rev_ / 360.0 + phase_));
}

}  // namespace gyrocal::sim
