#include "tests/support/virtual_lab/held_out.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <stdexcept>

#include "lcmtypes/text/number.hpp"

namespace gyrocal::virtual_lab {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// One sensor's running bin and integrals, for the floor and every candidate.
struct Track {
    struct PerCandidate {
        std::unique_ptr<compensator::SensorCompensator> comp;  // null: no set for this sensor
        double sum_err = 0;
        bool bad = false;  // a sample of the current bin was not compensated
        bool has_last = false;
        double last_err = 0;
    };
    int n = 0;
    double first_t_s = 0, last_t_s = 0;
    double sum_temp = 0, sum_die = 0, sum_floor = 0, sum_floor_meas = 0;
    double last_floor = 0, last_floor_meas = 0;
    bool has_last_floor = false;
    std::vector<PerCandidate> cands;
};

class Recorder : public sim::RigSink {
public:
    Recorder(sim::Rig& rig, const HeldOutProfile& p, const std::vector<Candidate>& candidates,
             const compensator::CompensatorOptions& options, HeldOutResult& out)
        : rig_(rig), p_(p), out_(out) {
        const sim::RigConfig& rc = rig.config();
        record_start_utime_ =
            rc.start_utime + static_cast<int64_t>(std::llround(p.lead_in_s * 1e6));
        per_bin_ = std::max(1L, std::lround(p.bin_s * rc.sample_rate_hz));
        out_.bin_s = static_cast<double>(per_bin_) / rc.sample_rate_hz;
        for (const sim::UnitTruth& u : rig.units()) {
            SensorHeldOut s;
            s.sensor_id = u.sensor_id;
            s.err_dps.resize(candidates.size());
            s.angle_deg.assign(candidates.size(), 0.0);
            s.not_compensated.assign(candidates.size(), 0);
            out_.sensors.push_back(std::move(s));
            Track t;
            t.cands.resize(candidates.size());
            for (size_t k = 0; k < candidates.size(); ++k) {
                auto it = candidates[k].find(u.sensor_id);
                if (it == candidates[k].end()) continue;
                t.cands[k].comp = std::make_unique<compensator::SensorCompensator>(options);
                const compensator::SetResult r = t.cands[k].comp->SetCoefficients(it->second);
                if (r.outcome == compensator::SetOutcome::kRejected)
                    throw std::invalid_argument("held-out: candidate " + std::to_string(k) +
                                                " set of " + u.sensor_id +
                                                " rejected by the compensator: " + r.detail);
                // The rig powers its units when it starts (it announces so on POWER_<id>), so a
                // warm-up term counts from there, not from the record's first sample.
                t.cands[k].comp->PowerOn(rc.start_utime);
            }
            tracks_.push_back(std::move(t));
        }
    }

    bool finished() const { return finished_; }

    void OnChamber(const sim::ChamberReading& r) override {
        if (r.utime < record_start_utime_ || finished_) return;
        if (!started_) {
            started_ = true;
            Command(0);
            return;
        }
        const sim::ChamberModel& ch = rig_.chamber();
        if (ch.reference_c() != ch.setpoint_c()) return;  // still ramping
        if (waypoint_ + 1 < p_.waypoints_c.size()) {
            Command(waypoint_ + 1);  // a continuous ramp: on at once
            return;
        }
        if (!hold_since_utime_) hold_since_utime_ = r.utime;
        if (static_cast<double>(r.utime - *hold_since_utime_) * 1e-6 >= p_.hold_s) {
            finished_ = true;
            out_.duration_s = static_cast<double>(r.utime - record_start_utime_) * 1e-6;
            rig_.StopAfterCurrentEvent();
        }
    }

    void OnGyro(const sim::GyroReading& r, const sim::GyroTruth& truth) override {
        if (!started_ || finished_) return;
        const size_t i = static_cast<size_t>(r.unit_index);
        const sim::UnitTruth& u = rig_.units()[i];
        Track& t = tracks_[i];
        SensorHeldOut& s = out_.sensors[i];
        const double t_s = static_cast<double>(r.utime - record_start_utime_) * 1e-6;
        const double dt_s = t_s - t.last_t_s;
        // The perfect models: truth at the die, and truth at the measured temperature. Effects
        // (when switched on in the rig) are part of the truth, as the rig reports them at the die.
        const double sens_factor = truth.effect_sens_factor;
        const double floor = (r.gyro_v - truth.offset_v - truth.effect_offset_v) /
                                 (truth.sensitivity_v_per_dps * sens_factor) -
                             truth.rate_true_dps;
        const double die_meas_c = r.temp_c - u.temp_sensor_offset_c;
        const double floor_meas = (r.gyro_v - u.OffsetV(die_meas_c) - truth.effect_offset_v) /
                                      (u.SensitivityVPerDps(die_meas_c) * sens_factor) -
                                  truth.rate_true_dps;
        if (t.has_last_floor) {
            s.floor_angle_deg += 0.5 * (t.last_floor + floor) * dt_s;
            s.floor_meas_angle_deg += 0.5 * (t.last_floor_meas + floor_meas) * dt_s;
        }
        t.has_last_floor = true;
        t.last_floor = floor;
        t.last_floor_meas = floor_meas;
        if (t.n == 0) t.first_t_s = t_s;
        ++t.n;
        t.sum_temp += r.temp_c;
        t.sum_die += truth.die_c;
        t.sum_floor += floor;
        t.sum_floor_meas += floor_meas;
        const compensator::Sample cs = compensator::SampleOf(r);
        for (size_t k = 0; k < t.cands.size(); ++k) {
            Track::PerCandidate& c = t.cands[k];
            if (!c.comp) {
                c.bad = true;
                continue;
            }
            const compensator::ApplyResult a = c.comp->Apply(cs);
            if (a.status != compensator::ApplyStatus::kOk) {
                c.bad = true;
                c.has_last = false;  // do not integrate across the hole
                ++s.not_compensated[k];
                continue;
            }
            const double err = a.out.rate_dps - truth.rate_true_dps;
            if (c.has_last) s.angle_deg[k] += 0.5 * (c.last_err + err) * dt_s;
            c.has_last = true;
            c.last_err = err;
            c.sum_err += err;
        }
        t.last_t_s = t_s;
        if (t.n == per_bin_) CloseBin(t, s);
    }

private:
    void Command(size_t index) {
        waypoint_ = index;
        const auto res = rig_.ChamberCommand(static_cast<int64_t>(index) + 1, p_.waypoints_c[index],
                                             p_.ramp_c_per_min);
        if (!res.accepted) throw std::invalid_argument("held-out: chamber refused: " + res.reason);
    }

    void CloseBin(Track& t, SensorHeldOut& s) {
        const double n = t.n;
        s.t_s.push_back(0.5 * (t.first_t_s + t.last_t_s));
        s.temp_c.push_back(t.sum_temp / n);
        s.die_c.push_back(t.sum_die / n);
        s.floor_dps.push_back(t.sum_floor / n);
        s.floor_meas_dps.push_back(t.sum_floor_meas / n);
        for (size_t k = 0; k < t.cands.size(); ++k) {
            Track::PerCandidate& c = t.cands[k];
            s.err_dps[k].push_back(c.bad ? kNaN : c.sum_err / n);
            c.sum_err = 0;
            c.bad = false;
        }
        t.n = 0;
        t.sum_temp = t.sum_die = t.sum_floor = t.sum_floor_meas = 0;
    }

    sim::Rig& rig_;
    const HeldOutProfile& p_;
    HeldOutResult& out_;
    std::vector<Track> tracks_;
    int64_t record_start_utime_ = 0;
    long per_bin_ = 1;
    bool started_ = false;
    bool finished_ = false;
    size_t waypoint_ = 0;
    std::optional<int64_t> hold_since_utime_;
};

}  // namespace

void HeldOutProfile::Validate(const sim::RigConfig& rig) const {
    if (waypoints_c.empty())
        throw std::invalid_argument("held-out waypoints_c: at least one is needed");
    for (double w : waypoints_c) {
        if (!std::isfinite(w) || w < rig.thermal.min_setpoint_c || w > rig.thermal.max_setpoint_c)
            throw std::invalid_argument("held-out waypoints_c: " + text::Sig(w) +
                                        " degC; valid: " + text::Sig(rig.thermal.min_setpoint_c) +
                                        " .. " + text::Sig(rig.thermal.max_setpoint_c) +
                                        " (the chamber's range)");
    }
    if (!(ramp_c_per_min > 0.0 && ramp_c_per_min <= rig.thermal.ramp_c_per_min))
        throw std::invalid_argument("held-out ramp_c_per_min: " + text::Sig(ramp_c_per_min) +
                                    "; valid: > 0 and <= the chamber's " +
                                    text::Sig(rig.thermal.ramp_c_per_min));
    if (!(hold_s >= 0.0 && hold_s <= 1e6))
        throw std::invalid_argument("held-out hold_s: valid 0 .. 1e6 s");
    if (!(lead_in_s >= 0.0 && lead_in_s <= 1e7))
        throw std::invalid_argument("held-out lead_in_s: valid 0 .. 1e7 s");
    if (!(bin_s * rig.sample_rate_hz >= 2.0 && bin_s <= 3600.0))
        throw std::invalid_argument("held-out bin_s: " + text::Sig(bin_s) +
                                    "; valid: >= 2 samples and <= 3600 s");
}

compensator::CompensatorOptions ClippedOptions() {
    compensator::CompensatorOptions o = compensator::CompensatorOptions::Defaults();
    o.range_policy = model::RangePolicy::kClip;
    return o;
}

HeldOutResult EvaluateHeldOut(const sim::RigConfig& rig_config, const HeldOutProfile& profile,
                              const std::vector<Candidate>& candidates,
                              const compensator::CompensatorOptions& options) {
    profile.Validate(rig_config);
    sim::Rig rig(rig_config);
    HeldOutResult out;
    Recorder recorder(rig, profile, candidates, options, out);
    // Cap: lead-in + every leg at the ordered ramp + the hold + 2 h of settling slack.
    double legs_c = 0, from_c = rig_config.thermal.start_temp_c;
    for (double w : profile.waypoints_c) {
        legs_c += std::abs(w - from_c);
        from_c = w;
    }
    const double cap_s =
        profile.lead_in_s + legs_c / profile.ramp_c_per_min * 60.0 + profile.hold_s + 7200.0;
    rig.RunUntil(rig_config.start_utime + static_cast<int64_t>(cap_s * 1e6), recorder);
    if (!recorder.finished())
        throw std::runtime_error("held-out: the profile did not finish within " + text::Sig(cap_s) +
                                 " s");
    return out;
}

Score ScoreBins(const std::vector<double>& err_dps, const std::vector<double>& temp_c,
                double range_min_c, double range_max_c, double angle_deg, double duration_s) {
    Score s;
    double sum2 = 0;
    int n = 0;
    for (size_t i = 0; i < err_dps.size() && i < temp_c.size(); ++i) {
        const double e = err_dps[i];
        if (!std::isfinite(e)) continue;
        sum2 += e * e;
        ++n;
        if (temp_c[i] >= range_min_c && temp_c[i] <= range_max_c) {
            s.max_in_dps = std::max(s.max_in_dps, std::abs(e));
            ++s.bins_in;
        } else {
            s.max_out_dps = std::max(s.max_out_dps, std::abs(e));
            ++s.bins_out;
        }
    }
    s.rms_dps = n > 0 ? std::sqrt(sum2 / n) : kNaN;
    s.drift_dph = duration_s > 0 ? angle_deg / (duration_s / 3600.0) : kNaN;
    return s;
}

model::CoeffSet TruthSet(const sim::UnitTruth& u, double min_c, double max_c) {
    auto quadratic = [&](const char* quantity, const std::array<double, 3>& c) {
        model::Model m;
        m.quantity = quantity;
        m.term_names = model::PolynomialTerms(2);
        m.coeffs = Eigen::Vector3d(c[0], c[1], c[2]);
        m.covariance = Eigen::MatrixXd::Zero(3, 3);
        m.t0_c = sim::kTruthT0C + u.temp_sensor_offset_c;
        m.temp_min_c = min_c;
        m.temp_max_c = max_c;
        m.residual_rms = 0;
        m.n_points = 0;
        m.condition_number = 1;
        m.method = "truth";
        return m;
    };
    model::CoeffSet set;
    set.sensor_id = u.sensor_id;
    set.source = "truth";
    set.offset = quadratic(model::kOffsetQuantity, u.offset_coeffs);
    set.sensitivity = quadratic(model::kSensitivityQuantity, u.sensitivity_coeffs);
    return set;
}

}  // namespace gyrocal::virtual_lab
