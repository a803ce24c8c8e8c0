#include "processors/noise/allan_plot.hpp"

#include <cmath>

#include "lcmtypes/text/number.hpp"

namespace gyrocal::noise {

namespace {

double Finite0(double v) { return std::isfinite(v) ? v : 0.0; }

}  // namespace

plot::Figure MakeAllanPlot(const AllanPlotInput& in) {
    const double s = in.sensitivity_v_per_dps.value_or(1.0);
    const std::string unit = in.sensitivity_v_per_dps ? "deg/s" : "V";
    const double n = Finite0(in.arw_v_rthz) / s, b = Finite0(in.bias_v) / s,
                 k = Finite0(in.rrw_v_rts) / s;
    plot::Figure f;
    f.name = in.sensor_id + "_allan";
    f.title = in.sensor_id + ": Allan deviation (IEEE 952 terms)";
    f.xlabel = "tau [s]";
    f.ylabel = "sigma_A [" + unit + "]";
    f.log_x = f.log_y = true;
    plot::Table t;
    t.name = f.name;
    t.comment = "sensor " + in.sensor_id + ": overlapping Allan deviation [" + unit +
                "] of the still, thermally quiet stretches";
    t.columns = {"tau_s", "adev", "adev_lo", "adev_hi", "fit", "arw_line", "bias_line", "rrw_line"};
    for (size_t i = 0; i < in.tau_s.size(); ++i) {
        const double tau = in.tau_s[i];
        auto at = [&](const std::vector<double>& v) { return i < v.size() ? v[i] / s : NAN; };
        t.rows.push_back({tau, at(in.adev_v), at(in.adev_lo_v), at(in.adev_hi_v),
                          std::sqrt(n * n / tau + b * b + k * k * tau / 3.0),
                          n > 0 ? n / std::sqrt(tau) : NAN, b > 0 ? b : NAN,
                          k > 0 ? k * std::sqrt(tau / 3.0) : NAN});
    }
    f.tables.push_back(std::move(t));
    using plot::Style;
    // yerrorbars in gnuplot take x, y, ylow, yhigh; the figure library's error bars take a
    // half-width, so the interval is drawn as a band under the points.
    f.series = {{f.name, Style::kBand, {1, 3, 4}, "68 % interval", "", 0},
                {f.name, Style::kPoints, {1, 2}, "measured", "", 0}};
    if (n > 0 || b > 0 || k > 0)
        f.series.push_back(
            {f.name, Style::kLines, {1, 5}, "fit sqrt(N^2/tau + B^2 + K^2 tau/3)", "", 0});
    // An asymptote only for a fitted term: a term the data could not reach (e.g. K on a run whose
    // longest still stretch is short) has no line, and its key entry would claim one.
    struct Asymptote {
        double value;  // [unit, unit/sqrt(Hz) or unit/sqrt(s)] the fitted term
        int column;    // its line's column of the table
        const char* label;
        std::string unit;
        int dash;
    };
    for (const Asymptote& a : {Asymptote{n, 6, "slope -1/2: N = ", unit + "/sqrt(Hz)", 2},
                               Asymptote{b, 7, "slope 0: B = ", unit, 3},
                               Asymptote{k, 8, "slope +1/2: K = ", unit + "/sqrt(s)", 4}}) {
        if (a.value > 0)
            f.series.push_back({f.name,
                                Style::kLines,
                                {1, a.column},
                                a.label + text::Sig(a.value, 3) + " " + a.unit,
                                "",
                                a.dash});
    }
    return f;
}

}  // namespace gyrocal::noise
