#include "plot.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <sstream>

#include "bins.hpp"

namespace gyrocal::analysis {

namespace {

// "?" is gnuplot's missing-value marker (set datafile missing "?").
std::string Num(double v) {
    if (!std::isfinite(v)) return "?";
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.9g", v);
    return buf;
}

// 3 significant digits, for titles.
std::string Short(double v) {
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.3g", v);
    return buf;
}

// Text safe inside a gnuplot double-quoted string.
std::string Quote(const std::string& s) {
    std::string out;
    for (char ch : s) {
        if (ch == '"' || ch == '\\') out += '\\';
        out += ch;
    }
    return out;
}

// The script header: both terminals, one output each (the plot command is repeated).
std::string Script(const std::string& name, const std::string& title, const std::string& xlabel,
                   const std::string& ylabel, const std::string& plot_command) {
    std::ostringstream s;
    s << "# gyrocal analyze --plot: " << name << "\n"
      << "set datafile missing \"?\"\n"
      << "set title \"" << Quote(title) << "\" noenhanced\n"
      << "set xlabel \"" << Quote(xlabel) << "\" noenhanced\n"
      << "set ylabel \"" << Quote(ylabel) << "\" noenhanced\n"
      << "set grid\nset key outside top center horizontal noenhanced\n";
    for (const char* term : {"png", "svg"}) {
        if (std::string(term) == "png")
            s << "set terminal pngcairo size 1000,600\n";
        else
            s << "set terminal svg size 1000,600 dynamic\n";
        s << "set output \"" << Quote(name) << "." << term << "\"\n" << plot_command << "\n";
    }
    s << "set output\n";
    return s.str();
}

std::optional<model::Evaluator> EvaluatorOf(const std::optional<model::Model>& m) {
    if (!m) return std::nullopt;
    try {
        return model::Evaluator(*m);
    } catch (const model::ModelError&) {
        return std::nullopt;  // an unusable model is simply not drawn
    }
}

}  // namespace

PlotSet MakePlots(const SensorRun& run, const SensorResult& r, const AnalysisOptions& o) {
    PlotSet set;
    const BinnedRun binned(run, o.bins);
    const std::vector<Bin>& bins = binned.bins();
    const std::optional<model::Evaluator> before = EvaluatorOf(r.declared_offset);
    const std::optional<model::Evaluator> after = EvaluatorOf(r.extended_offset);
    const Eigen::VectorXd vb = before ? binned.Values(before->model()) : Eigen::VectorXd();
    const Eigen::VectorXd va = after ? binned.Values(after->model()) : Eigen::VectorXd();
    const std::string id = r.sensor_id;

    // Residuals per bin: one data file for the time and temperature plots.
    std::ostringstream dat;
    dat << "# sensor " << id << ": still bins of " << Num(o.bins.bin_s) << " s\n"
        << "# time_h temp_c resid_before_mv resid_after_mv\n";
    for (size_t i = 0; i < bins.size(); ++i) {
        const Bin& b = bins[i];
        const auto k = static_cast<Eigen::Index>(i);
        const double rb = before ? b.gyro_v - vb[k] : kNan;
        const double ra = after ? b.gyro_v - va[k] : kNan;
        dat << Num((b.mid_utime - static_cast<double>(run.first_sample_utime)) * 1e-6 / 3600.0)
            << " " << Num(b.temp_c) << " " << Num(rb * 1e3) << " " << Num(ra * 1e3) << "\n";
    }
    const std::string res_dat = id + "_residual.dat";
    set.files.push_back({res_dat, dat.str()});
    const std::string after_label =
        r.added.empty() ? "after (declared terms refitted on all bins: nothing added)"
                        : "after (extended model)";
    auto residual_plot = [&](const std::string& suffix, int xcol, const std::string& xlabel) {
        const std::string name = id + "_residual_" + suffix;
        const std::string cmd = "plot \"" + res_dat + "\" using " + std::to_string(xcol) +
                                ":3 with points pt 7 ps 0.5 title \"before (declared model)\", \"" +
                                res_dat + "\" using " + std::to_string(xcol) +
                                ":4 with points pt 7 ps 0.5 title \"" + after_label + "\"";
        set.files.push_back(
            {name + ".gp", Script(name, id + ": offset residual vs " + suffix + " - " + r.verdict,
                                  xlabel, "residual [mV]", cmd)});
        set.scripts.push_back(name + ".gp");
        set.images.push_back(name + ".png");
        set.images.push_back(name + ".svg");
    };
    residual_plot("time", 1, "time since first sample [h]");
    residual_plot("temp", 2, "temperature [degC]");

    // Each added offset effect against its regressor, with the fitted effect over it.
    if (!after) return set;
    const model::Model& ext = after->model();
    for (const AddedEffect& a : r.added) {
        const auto it = std::find(ext.term_names.begin(), ext.term_names.end(), a.term);
        if (it == ext.term_names.end()) continue;  // sf_asymmetry: a sensitivity term
        const auto k = static_cast<Eigen::Index>(it - ext.term_names.begin());
        struct Row {
            double x, partial_mv, effect_mv;
        };
        std::vector<Row> rows;
        const gyrocal_tracker_config_t config = model::TrackerConfigFor(ext);
        for (size_t i = 0; i < bins.size(); ++i) {
            const Bin& b = bins[i];
            const Eigen::VectorXd phi = after->TermValues(binned.Inputs(i, config));
            if (!phi.allFinite()) continue;
            const double others = phi.dot(ext.coeffs) - phi[k] * ext.coeffs[k];
            rows.push_back({phi[k], (b.gyro_v - others) * 1e3, phi[k] * ext.coeffs[k] * 1e3});
        }
        // Sorted by the regressor so the fitted effect is drawn as one line.
        std::sort(rows.begin(), rows.end(), [](const Row& p, const Row& q) { return p.x < q.x; });
        const std::string name = id + "_effect_" + a.effect;
        std::ostringstream ed;
        ed << "# sensor " << id << ": effect " << a.effect << ", term " << a.term
           << ", coefficient " << Num(a.coefficient) << " +- " << Num(a.stderr_) << " " << a.unit
           << "\n# regressor partial_resid_mv fitted_effect_mv\n";
        for (const Row& row : rows)
            ed << Num(row.x) << " " << Num(row.partial_mv) << " " << Num(row.effect_mv) << "\n";
        set.files.push_back({name + ".dat", ed.str()});
        const std::string cmd = "plot \"" + name +
                                ".dat\" using 1:2 with points pt 7 ps 0.5 title \"residual without "
                                "this term\", \"" +
                                name + ".dat\" using 1:3 with lines lw 2 title \"fitted " +
                                Quote(a.term) + ": " + Short(a.coefficient) + " +- " +
                                Short(a.stderr_) + " " + Quote(a.unit) + "\"";
        set.files.push_back(
            {name + ".gp", Script(name, id + ": " + a.effect + " (" + a.term + ")",
                                  "regressor " + a.term, "partial residual [mV]", cmd)});
        set.scripts.push_back(name + ".gp");
        set.images.push_back(name + ".png");
        set.images.push_back(name + ".svg");
    }
    return set;
}

}  // namespace gyrocal::analysis
