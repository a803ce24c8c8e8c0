#include "processors/analysis/plot.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>

#include "lcmtypes/text/number.hpp"
#include "processors/analysis/bins.hpp"

namespace gyrocal::analysis {

namespace {

// 3 significant digits, for titles.
std::optional<model::Evaluator> EvaluatorOf(const std::optional<model::Model>& m) {
    if (!m) return std::nullopt;
    try {
        return model::Evaluator(*m);
    } catch (const model::ModelError&) {
        return std::nullopt;  // an unusable model is simply not drawn
    }
}

}  // namespace

plot::Table ResidualTable(const BinnedRun& binned, const SensorResult& r) {
    const std::optional<model::Evaluator> before = EvaluatorOf(r.declared_offset);
    const std::optional<model::Evaluator> after = EvaluatorOf(r.extended_offset);
    const Eigen::VectorXd vb = before ? binned.Values(before->model()) : Eigen::VectorXd();
    const Eigen::VectorXd va = after ? binned.Values(after->model()) : Eigen::VectorXd();
    const double bin_s = binned.bin_s();
    plot::Table t{r.sensor_id + "_residual",
                  "sensor " + r.sensor_id + ": still bins of " + text::Sig(bin_s, 3) + " s",
                  {"time_h", "temp_c", "resid_before_mv", "resid_after_mv"},
                  {}};
    const int64_t first = binned.run().first_sample_utime;
    for (size_t i = 0; i < binned.size(); ++i) {
        const Bin& b = binned.bins()[i];
        const auto k = static_cast<Eigen::Index>(i);
        const double rb = before ? b.gyro_v - vb[k] : kNan;
        const double ra = after ? b.gyro_v - va[k] : kNan;
        t.rows.push_back({(b.mid_utime - static_cast<double>(first)) * 1e-6 / 3600.0, b.temp_c,
                          rb * 1e3, ra * 1e3});
    }
    return t;
}

namespace {

// Each added offset effect against its regressor, with the fitted effect over it.
std::optional<plot::Figure> EffectFigure(const BinnedRun& binned, const SensorResult& r,
                                         const model::Evaluator& after, const AddedEffect& a) {
    const model::Model& ext = after.model();
    const auto it = std::find(ext.term_names.begin(), ext.term_names.end(), a.term);
    if (it == ext.term_names.end()) return std::nullopt;  // sf_asymmetry: a sensitivity term
    const auto k = static_cast<Eigen::Index>(it - ext.term_names.begin());
    const std::string name = r.sensor_id + "_effect_" + a.effect;
    plot::Table t{name,
                  "sensor " + r.sensor_id + ": effect " + a.effect + ", term " + a.term +
                      ", coefficient " + text::Sig(a.coefficient, 3) + " +- " +
                      text::Sig(a.stderr_, 3) + " " + a.unit,
                  {"regressor", "partial_resid_mv", "fitted_effect_mv"},
                  {}};
    const gyrocal_tracker_config_t config = model::TrackerConfigFor(ext);
    for (size_t i = 0; i < binned.size(); ++i) {
        const Bin& b = binned.bins()[i];
        const Eigen::VectorXd phi = after.TermValues(binned.Inputs(i, config));
        if (!phi.allFinite()) continue;
        const double others = phi.dot(ext.coeffs) - phi[k] * ext.coeffs[k];
        t.rows.push_back({phi[k], (b.gyro_v - others) * 1e3, phi[k] * ext.coeffs[k] * 1e3});
    }
    // Sorted by the regressor so the fitted effect is drawn as one line.
    std::sort(t.rows.begin(), t.rows.end(),
              [](const auto& p, const auto& q) { return p[0] < q[0]; });
    plot::Figure f;
    f.name = name;
    f.title = r.sensor_id + ": " + a.effect + " (" + a.term + ")";
    f.xlabel = "regressor " + a.term;
    f.ylabel = "partial residual [mV]";
    f.tables = {t};
    f.series = {{name, plot::Style::kPoints, {1, 2}, "residual without this term", ""},
                {name,
                 plot::Style::kLines,
                 {1, 3},
                 "fitted " + a.term + ": " + text::Sig(a.coefficient, 3) + " +- " +
                     text::Sig(a.stderr_, 3) + " " + a.unit,
                 ""}};
    return f;
}

// The periodogram of the final residual (analyze.hpp step 8 diagnostics), its peak marked and
// labelled with its period and amplitude.
std::optional<plot::Figure> PeriodogramFigure(const SensorResult& r) {
    const ResidualDiagnostics& d = r.residual;
    if (d.periodogram.empty() || !std::isfinite(d.period_s)) return std::nullopt;
    const std::string name = r.sensor_id + "_periodogram";
    plot::Table t{
        name,
        "sensor " + r.sensor_id + ": sinusoid fitted to the still residual at each period",
        {"period_s", "amplitude_mv"},
        {}};
    for (const CurvePoint& p : d.periodogram) t.rows.push_back({p.x, p.y * 1e3});
    // A period of 100 s or more in whole seconds, not "1.57e+03".
    const std::string period = text::Printf(d.period_s >= 100.0 ? "%.0f" : "%.3g", d.period_s);
    const std::string label = "peak: period " + period + " s, amplitude " +
                              text::Sig(d.period_amplitude_v * 1e3, 3) + " mV (" +
                              text::Sig(d.period_power_ratio, 3) + " x the median power)";
    plot::Table peak{name + "_peak",
                     label,
                     {"period_s", "amplitude_mv"},
                     {{d.period_s, d.period_amplitude_v * 1e3}}};
    plot::Table mark{name + "_peak_mark",
                     "a vertical line at the peak's period",
                     {"period_s", "amplitude_mv"},
                     {{d.period_s, 0.0}, {d.period_s, d.period_amplitude_v * 1e3}}};
    plot::Figure f;
    f.name = name;
    f.title = r.sensor_id + ": periodogram of the still residual - " + label;
    f.xlabel = "period [s]";
    f.ylabel = "amplitude [mV]";
    f.log_x = true;
    f.tables = {t, peak, mark};
    f.series = {{name, plot::Style::kLines, {1, 2}, "residual (final model)", ""},
                {mark.name, plot::Style::kLines, {1, 2}, "", "#d62728", 2},
                {peak.name, plot::Style::kPoints, {1, 2}, label, "#d62728"}};
    return f;
}

// The residual's autocorrelation against lag, with the band white noise stays in (95 %).
std::optional<plot::Figure> AutocorrFigure(const SensorResult& r) {
    const ResidualDiagnostics& d = r.residual;
    if (d.autocorr.size() < 2 || r.n_bins <= 0) return std::nullopt;
    const std::string name = r.sensor_id + "_autocorr";
    const double band = 1.96 / std::sqrt(static_cast<double>(r.n_bins));
    plot::Table t{name,
                  "sensor " + r.sensor_id + ": autocorrelation of the still residual",
                  {"lag_s", "autocorr", "white_lo", "white_hi"},
                  {}};
    for (const CurvePoint& p : d.autocorr) t.rows.push_back({p.x, p.y, -band, band});
    plot::Figure f;
    f.name = name;
    f.title = r.sensor_id + ": autocorrelation of the still residual (lag-1 " +
              text::Sig(d.lag1_autocorr, 3) + ")";
    f.xlabel = "lag [s]";
    f.ylabel = "autocorrelation [1]";
    f.tables = {t};
    f.series = {{name, plot::Style::kBand, {1, 3, 4}, "white noise (95 %)", ""},
                {name, plot::Style::kLines, {1, 2}, "residual (final model)", ""}};
    return f;
}

}  // namespace

std::vector<plot::Figure> MakePlots(const SensorRun& run, const SensorResult& r,
                                    const AnalysisOptions& o) {
    const BinnedRun binned(run, o.bins);
    const plot::Table residual = ResidualTable(binned, r);
    const std::string after_label =
        r.added.empty() ? "after (declared terms refitted on all bins: nothing added)"
                        : "after (extended model)";
    std::vector<plot::Figure> figures;
    for (const auto& [suffix, xcol, xlabel] :
         {std::tuple<std::string, int, std::string>{"time", 1, "time since first sample [h]"},
          {"temp", 2, "temperature [degC]"}}) {
        plot::Figure f;
        f.name = r.sensor_id + "_residual_" + suffix;
        f.title = r.sensor_id + ": offset residual vs " + suffix + " - " + r.verdict;
        f.xlabel = xlabel;
        f.ylabel = "residual [mV]";
        f.tables = {residual};
        f.series = {{residual.name, plot::Style::kPoints, {xcol, 3}, "before (declared model)", ""},
                    {residual.name, plot::Style::kPoints, {xcol, 4}, after_label, ""}};
        figures.push_back(std::move(f));
    }
    if (auto f = PeriodogramFigure(r)) figures.push_back(std::move(*f));
    if (auto f = AutocorrFigure(r)) figures.push_back(std::move(*f));
    const std::optional<model::Evaluator> after = EvaluatorOf(r.extended_offset);
    if (!after) return figures;
    for (const AddedEffect& a : r.added)
        if (auto f = EffectFigure(binned, r, *after, a)) figures.push_back(std::move(*f));
    return figures;
}

}  // namespace gyrocal::analysis
