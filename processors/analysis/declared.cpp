#include "declared.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "candidates.hpp"
#include "fit/levels.hpp"

namespace gyrocal::analysis::detail {

void ErrorsOn(const std::vector<Bin>& hold, const model::Evaluator& offset,
              const std::optional<model::Evaluator>& sens, double period_s, int64_t first_utime,
              ErrorFigures* e) {
    double ss_v = 0.0, ss_r = 0.0, angle = 0.0, dur = 0.0;
    int n = 0;
    bool rate_ok = sens.has_value();
    for (const Bin& b : hold) {
        const model::ModelInputs in = b.Inputs(first_utime);
        const double r = b.gyro_v - offset.Value(in, model::RangePolicy::kExtrapolate);
        if (!std::isfinite(r)) continue;
        ss_v += r * r;
        ++n;
        if (rate_ok) {
            model::ModelInputs si = in;
            si.direction = 0.0;  // at rest: no rotation direction (a direction term contributes 0)
            const double s = sens->Value(si, model::RangePolicy::kClip);
            if (!std::isfinite(s) || s == 0.0) {
                rate_ok = false;
                continue;
            }
            const double rate = r / s;
            ss_r += rate * rate;
            const double d = b.n * period_s;
            angle += rate * d;
            dur += d;
        }
    }
    if (n == 0) return;
    e->offset_rms_v = std::sqrt(ss_v / n);
    if (rate_ok && dur > 0) {
        e->rate_rms_dps = std::sqrt(ss_r / n);
        e->drift_dph = std::fabs(angle) / dur * 3600.0;
    }
}

double MeanInverseSensitivity(const model::Evaluator& sens, const std::vector<Bin>& bins,
                              int64_t first_utime, bool plateau_only) {
    double sum_inv = 0.0;
    int n = 0;
    for (const Bin& b : bins) {
        if (plateau_only && b.plateau < 0) continue;
        model::ModelInputs in = b.Inputs(first_utime);
        in.direction = 0.0;  // at rest: no rotation direction
        const double s = sens.Value(in, model::RangePolicy::kClip);
        if (!std::isfinite(s) || s == 0.0) return std::numeric_limits<double>::quiet_NaN();
        sum_inv += 1.0 / std::fabs(s);
        ++n;
    }
    return n > 0 ? sum_inv / n : std::numeric_limits<double>::quiet_NaN();
}

void ExpectedAfter(const LsFit& fit, const Eigen::MatrixXd& x_held, const std::vector<Bin>& held,
                   const std::optional<model::Evaluator>& sens, int64_t first_utime,
                   SensorResult* r) {
    const Eigen::Index n = x_held.rows(), p = fit.coeffs.size();
    const Eigen::Index n_train = fit.residuals.size();
    if (n == 0 || n_train <= p) return;
    // Mean prediction variance x' C x over the held-out bins: how far the coefficients fitted
    // before the stretch may put the model off on it, by their own (robust) covariance.
    const double pred_var =
        (x_held * fit.covariance).cwiseProduct(x_held).rowwise().sum().mean();
    const double resid_var = fit.rss / static_cast<double>(n_train - p);
    if (!(pred_var >= 0.0) || !std::isfinite(resid_var)) return;
    r->prediction_rms_v = std::sqrt(pred_var);
    r->expected_after_offset_rms_v = std::sqrt(resid_var + pred_var);
    if (!sens) return;
    const double inv_s = MeanInverseSensitivity(*sens, held, first_utime, false);
    r->expected_after_rate_rms_dps = r->expected_after_offset_rms_v * inv_s;
    r->prediction_rms_dps = r->prediction_rms_v * inv_s;
}

std::vector<fit::FitPoint> PlateauPoints(const std::vector<PlateauInput>& plateaus,
                                         int64_t before_utime) {
    std::vector<fit::FitPoint> pts;
    for (const PlateauInput& p : plateaus) {
        if (p.end_utime > before_utime) continue;
        if (!std::isfinite(p.temp_mean_c) || !std::isfinite(p.gyro_mean_v) || !(p.gyro_sem_v > 0.0))
            continue;
        fit::FitPoint f;
        f.inputs.temp_c = p.temp_mean_c;
        f.y = p.gyro_mean_v;
        f.sigma_y = p.gyro_sem_v;
        f.id = p.plateau_id;
        pts.push_back(f);
    }
    return pts;
}

// The declared offset model on plateau means; nullopt with `why` when it cannot be fitted.
std::optional<model::Model> DeclaredOffset(const std::vector<fit::FitPoint>& pts,
                                           const AnalysisOptions& o, std::string* why) {
    std::vector<double> temps;
    for (const auto& p : pts) temps.push_back(p.inputs.temp_c);
    const auto levels = fit::TemperatureLevels(temps, o.same_level_tolerance_c);
    if (levels.size() < o.offset_terms.size()) {
        *why = "fewer plateau temperatures (" + std::to_string(levels.size()) +
               ") than declared offset terms (" + std::to_string(o.offset_terms.size()) + ")";
        return std::nullopt;
    }
    const fit::FitResult f =
        fit::FitWls(pts, o.offset_terms, RoundT0(levels.front().temp_c, levels.back().temp_c),
                    model::kOffsetQuantity);
    if (!f.ok()) {
        *why = f.detail;
        return std::nullopt;
    }
    return f.model;
}

// Model from a bin fit.
model::Model BinModel(const std::vector<std::string>& terms, double t0,
                      const std::vector<Bin>& bins, const LsFit& f) {
    model::Model m;
    m.quantity = model::kOffsetQuantity;
    m.term_names = terms;
    m.coeffs = f.coeffs;
    m.covariance = f.covariance;
    m.t0_c = t0;
    m.temp_min_c = INFINITY;
    m.temp_max_c = -INFINITY;
    for (const Bin& b : bins) {
        m.temp_min_c = std::min(m.temp_min_c, b.temp_c);
        m.temp_max_c = std::max(m.temp_max_c, b.temp_c);
    }
    m.residual_rms = std::sqrt(f.rss / static_cast<double>(bins.size()));
    m.n_points = static_cast<int32_t>(bins.size());
    m.method = "analysis";
    return m;
}

}  // namespace gyrocal::analysis::detail
