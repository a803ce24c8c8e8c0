#include "store/runreport/figures.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>
#include <tuple>

#include "processors/model/inputs.hpp"
#include "store/db/model_rows.hpp"

namespace gyrocal::runreport {

namespace {

constexpr int kCurvePoints = 101;

// The models of a calibration are evaluated as gyrocal history does (steady state).
model::ModelInputs At(const model::Evaluator& e, double temp_c) {
    return model::SteadyStateInputs(e.model(), temp_c);
}

std::optional<model::Evaluator> EvaluatorOf(const db::ModelRow& row) {
    try {
        return model::Evaluator(db::ToModel(row));
    } catch (const model::ModelError&) {
        return std::nullopt;  // not drawn; the coefficient section says why
    }
}

bool AnyFinite(const plot::Table& t) {
    for (const auto& r : t.rows)
        if (std::all_of(r.begin(), r.end(), [](double v) { return std::isfinite(v); })) return true;
    return false;
}

// Adds the series when its table has a finite row (and the table once).
void AddSeries(plot::Figure& f, const plot::Table& t, plot::Series s) {
    if (!AnyFinite(t)) return;
    if (std::none_of(f.tables.begin(), f.tables.end(),
                     [&](const plot::Table& x) { return x.name == t.name; }))
        f.tables.push_back(t);
    s.table = t.name;
    f.series.push_back(std::move(s));
}

// The curve and its band over the model's range: temp_c, value, low, high (value x scale).
plot::Table Curve(const model::Evaluator& e, const std::string& name, double scale, bool centred) {
    const model::Model& m = e.model();
    plot::Table t{
        name, "fitted curve and +-2 sigma band", {"temp_c", "fit", "band_low", "band_high"}, {}};
    const double lo = m.temp_min_c, hi = m.temp_max_c;
    if (!std::isfinite(lo) || !std::isfinite(hi) || hi < lo) return t;
    for (int i = 0; i < kCurvePoints; ++i) {
        const double temp = lo + (hi - lo) * i / (kCurvePoints - 1);
        const model::Evaluation v = e.Evaluate(At(e, temp), model::RangePolicy::kClip);
        const double mid = centred ? 0.0 : v.value * scale;
        const double half = kBandSigmas * std::sqrt(v.variance) * std::abs(scale);
        t.rows.push_back({temp, mid, mid - half, mid + half});
    }
    return t;
}

const char* kBandTitle = "fit +-2 sigma (coefficient covariance)";

plot::Figure Base(const std::string& name, const std::string& title, const std::string& xlabel,
                  const std::string& ylabel) {
    plot::Figure f;
    f.name = name;
    f.title = title;
    f.xlabel = xlabel;
    f.ylabel = ylabel;
    f.width_px = 640;
    f.height_px = 400;
    return f;
}

// [V] a plateau's uncertainty as the fitter weighted it.
double PlateauSigmaV(const db::PlateauRow& p, double slow_dps,
                     const std::optional<model::Evaluator>& sens) {
    const double s =
        sens ? std::abs(sens->Value(At(*sens, p.temp_mean_c), model::RangePolicy::kClip)) : NAN;
    return std::hypot(p.gyro_sem_v, std::isfinite(s) ? slow_dps * s : 0.0);
}

bool Used(const std::vector<int64_t>& ids, int64_t id) {
    return std::find(ids.begin(), ids.end(), id) != ids.end();
}

}  // namespace

int64_t TimeOrigin(const db::RunDetail& d) {
    int64_t t0 = std::numeric_limits<int64_t>::max();
    for (const auto& p : d.plateaus) t0 = std::min(t0, p.start_utime);
    for (const auto& s : d.sensitivity_points) t0 = std::min(t0, s.start_utime);
    if (t0 == std::numeric_limits<int64_t>::max()) return d.run.started_utime.value_or(0);
    // The run's start when it is on the same clock as the windows (it is: the sequencer's or the
    // source's message time), i.e. before them and not absurdly far.
    constexpr int64_t kWeekUs = 7LL * 24 * 3600 * 1000000;
    if (d.run.started_utime && *d.run.started_utime <= t0 && t0 - *d.run.started_utime < kWeekUs)
        return *d.run.started_utime;
    return t0;
}

namespace {

// The unit's calibration, evaluable (either may be missing or unusable), and the plateau set
// beside a final set fitted on every still sample.
struct Fits {
    std::optional<model::Evaluator> off, sens, plateau_off;
    std::vector<int64_t> used_plateaus;
};

// Offset vs temperature, and the offset residuals vs temperature and time.
void OffsetFigures(const UnitData& u, const std::string& stem, double slow_dps, int64_t t0,
                   const Fits& fit, std::vector<plot::Figure>& figures) {
    const std::string& id = u.sensor_id;
    plot::Table pts{
        stem + "_offset_pts", "plateau means", {"temp_c", "gyro_mean_v", "sigma_v"}, {}};
    plot::Table res{
        stem + "_resid", "plateau residuals", {"temp_c", "time_h", "resid_mv", "sigma_mv"}, {}};
    plot::Table unused{
        stem + "_resid_unused", "plateaus not in the fit", {"temp_c", "time_h", "resid_mv"}, {}};
    for (const auto& p : u.plateaus) {
        const double sigma = PlateauSigmaV(p, slow_dps, fit.sens);
        pts.rows.push_back({p.temp_mean_c, p.gyro_mean_v, sigma});
        if (!fit.off) continue;
        const double r_mv = (p.gyro_mean_v - fit.off->Value(At(*fit.off, p.temp_mean_c),
                                                            model::RangePolicy::kExtrapolate)) *
                            1e3;
        const double mid_h =
            (0.5 * (p.start_utime + p.end_utime) - static_cast<double>(t0)) / 3.6e9;
        if (Used(fit.used_plateaus, p.plateau_id))
            res.rows.push_back({p.temp_mean_c, mid_h, r_mv, sigma * 1e3});
        else
            unused.rows.push_back({p.temp_mean_c, mid_h, r_mv});
    }
    plot::Figure fo =
        Base(stem + "_offset", id + ": offset vs temperature", "temperature [degC]", "offset [V]");
    if (fit.off) {
        const plot::Table c = Curve(*fit.off, stem + "_offset_fit", 1.0, false);
        AddSeries(fo, c, {"", plot::Style::kBand, {1, 3, 4}, kBandTitle, "#9ecae1"});
        AddSeries(fo, c,
                  {"",
                   plot::Style::kLines,
                   {1, 2},
                   fit.plateau_off ? "final set (every still sample)" : "fitted offset",
                   "#1f77b4"});
    }
    if (fit.plateau_off) {
        const plot::Table c = Curve(*fit.plateau_off, stem + "_offset_plateau_fit", 1.0, false);
        AddSeries(
            fo, c,
            {"", plot::Style::kLines, {1, 2}, "plateau set (plateau means only)", "#ff7f0e", 2});
    }
    AddSeries(fo, pts, {"", plot::Style::kErrorBars, {1, 2, 3}, "plateau means", "#d62728"});
    if (!fo.series.empty()) figures.push_back(fo);
    if (!fit.off) return;
    // The band around zero is the fitted curve's own uncertainty.
    plot::Table band{stem + "_offset_band",
                     "+-2 sigma of the fitted offset",
                     {"temp_c", "zero", "low_mv", "high_mv"},
                     {}};
    band.rows = Curve(*fit.off, "tmp", 1e3, true).rows;
    plot::Figure frt = Base(stem + "_resid_temp", id + ": offset residual vs temperature",
                            "temperature [degC]", "plateau mean - fit [mV]");
    AddSeries(frt, band, {"", plot::Style::kBand, {1, 3, 4}, kBandTitle, "#9ecae1"});
    AddSeries(frt, res, {"", plot::Style::kErrorBars, {1, 3, 4}, "plateaus in the fit", "#d62728"});
    AddSeries(frt, unused,
              {"", plot::Style::kPoints, {1, 3}, "plateaus not in the fit", "#7f7f7f"});
    if (!frt.series.empty()) figures.push_back(frt);
    plot::Figure frh = Base(stem + "_resid_time", id + ": offset residual vs time",
                            "time since the run started [h]", "plateau mean - fit [mV]");
    AddSeries(frh, res, {"", plot::Style::kErrorBars, {2, 3, 4}, "plateaus in the fit", "#d62728"});
    AddSeries(frh, unused,
              {"", plot::Style::kPoints, {2, 3}, "plateaus not in the fit", "#7f7f7f"});
    if (!frh.series.empty()) figures.push_back(frh);
}

// Sensitivity [mV/(deg/s)] vs temperature, and the turns' residuals [%].
void SensitivityFigures(const UnitData& u, const std::string& stem, const Fits& fit,
                        std::vector<plot::Figure>& figures) {
    const std::string& id = u.sensor_id;
    plot::Table acc{stem + "_sens_pts",
                    "accepted turns",
                    {"temp_c", "sens_mv_per_dps", "sigma_mv_per_dps"},
                    {}};
    plot::Table rej{stem + "_sens_rej", "refused turns", {"temp_c", "sens_mv_per_dps"}, {}};
    plot::Table res{
        stem + "_sens_resid", "turn residuals", {"temp_c", "resid_pct", "sigma_pct"}, {}};
    for (const auto& s : u.turns) {
        if (!s.accepted) {
            rej.rows.push_back({s.temp_c, s.sensitivity_v_per_dps * 1e3});
            continue;
        }
        acc.rows.push_back(
            {s.temp_c, s.sensitivity_v_per_dps * 1e3, s.sensitivity_stderr_v_per_dps * 1e3});
        if (!fit.sens) continue;
        const double f = fit.sens->Value(At(*fit.sens, s.temp_c), model::RangePolicy::kExtrapolate);
        res.rows.push_back({s.temp_c, 100.0 * (s.sensitivity_v_per_dps - f) / f,
                            100.0 * s.sensitivity_stderr_v_per_dps / std::abs(f)});
    }
    plot::Figure fs = Base(stem + "_sens", id + ": sensitivity vs temperature",
                           "temperature [degC]", "sensitivity [mV/(deg/s)]");
    if (fit.sens) {
        const plot::Table c = Curve(*fit.sens, stem + "_sens_fit", 1e3, false);
        AddSeries(fs, c, {"", plot::Style::kBand, {1, 3, 4}, kBandTitle, "#9ecae1"});
        AddSeries(fs, c, {"", plot::Style::kLines, {1, 2}, "fitted sensitivity", "#1f77b4"});
    }
    AddSeries(fs, acc, {"", plot::Style::kErrorBars, {1, 2, 3}, "accepted turns", "#d62728"});
    AddSeries(fs, rej, {"", plot::Style::kPoints, {1, 2}, "refused turns", "#7f7f7f"});
    if (!fs.series.empty()) figures.push_back(fs);
    if (!fit.sens || !AnyFinite(res)) return;
    plot::Table band{stem + "_sens_band",
                     "+-2 sigma of the fitted sensitivity",
                     {"temp_c", "zero", "low_pct", "high_pct"},
                     {}};
    for (const auto& row : Curve(*fit.sens, "tmp", 1.0, false).rows) {
        const double half_pct = 100.0 * (row[3] - row[1]) / std::abs(row[1]);
        band.rows.push_back({row[0], 0.0, -half_pct, half_pct});
    }
    plot::Figure fr = Base(stem + "_sens_resid", id + ": sensitivity residual vs temperature",
                           "temperature [degC]", "turn - fit [%]");
    AddSeries(fr, band, {"", plot::Style::kBand, {1, 3, 4}, kBandTitle, "#9ecae1"});
    AddSeries(fr, res, {"", plot::Style::kErrorBars, {1, 2, 3}, "accepted turns", "#d62728"});
    figures.push_back(fr);
}

// The still bins' offset residual before (declared model) and after (the final set) from the
// analysis that made the final set ("residual_bins" of its JSON: time_h, temp_c, resid_before_mv,
// resid_after_mv), against time and temperature.
void ClosedLoopFigures(const UnitData& u, const std::string& stem,
                       std::vector<plot::Figure>& figures) {
    if (!u.final_analysis) return;
    const auto j = nlohmann::json::parse(u.final_analysis->result_json, nullptr, false);
    if (!j.is_object() || !j.contains("residual_bins") || !j["residual_bins"].contains("rows"))
        return;
    plot::Table t{stem + "_loop_resid",
                  "still bins: residual of the declared model and of the final set",
                  {"time_h", "temp_c", "resid_before_mv", "resid_after_mv"},
                  {}};
    for (const auto& row : j["residual_bins"]["rows"]) {
        if (!row.is_array() || row.size() != 4) continue;
        std::vector<double> r;
        for (const auto& v : row) r.push_back(v.is_number() ? v.get<double>() : NAN);
        t.rows.push_back(r);
    }
    const std::string& id = u.sensor_id;
    for (const auto& [suffix, x, xlabel] :
         {std::tuple{"_loop_resid_time", 1, "time since the first sample [h]"},
          std::tuple{"_loop_resid_temp", 2, "temperature [degC]"}}) {
        plot::Figure f =
            Base(stem + suffix, id + ": still-bin residual before and after the closed loop",
                 xlabel, "bin mean - model [mV]");
        AddSeries(f, t, {"", plot::Style::kPoints, {x, 3}, "declared model (before)", "#7f7f7f"});
        AddSeries(f, t, {"", plot::Style::kPoints, {x, 4}, "final set (after)", "#1f77b4"});
        if (!f.series.empty()) figures.push_back(f);
    }
}

}  // namespace

std::vector<plot::Figure> UnitFigures(const UnitData& u, const std::string& stem, double slow_dps,
                                      int64_t t0) {
    Fits fit;
    if (u.calibration) {
        fit.off = EvaluatorOf(u.calibration->set.offset);
        fit.sens = EvaluatorOf(u.calibration->set.sensitivity);
        fit.used_plateaus = u.calibration->set.plateau_ids;
    }
    if (u.plateau_set) {
        fit.plateau_off = EvaluatorOf(u.plateau_set->set.offset);
        fit.used_plateaus = u.plateau_set->set.plateau_ids;
    }
    std::vector<plot::Figure> figures;
    OffsetFigures(u, stem, slow_dps, t0, fit, figures);
    SensitivityFigures(u, stem, fit, figures);
    ClosedLoopFigures(u, stem, figures);
    return figures;
}

}  // namespace gyrocal::runreport
