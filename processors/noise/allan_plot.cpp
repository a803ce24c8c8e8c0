#include "allan_plot.hpp"

#include <cmath>
#include <cstdio>
#include <sstream>

namespace gyrocal::noise {

namespace {

std::string Num(double v) {
    if (!std::isfinite(v)) return "?";
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.9g", v);
    return buf;
}

std::string Short(double v) {
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.3g", v);
    return buf;
}

double Finite0(double v) { return std::isfinite(v) ? v : 0.0; }

}  // namespace

AllanPlot MakeAllanPlot(const AllanPlotInput& in) {
    AllanPlot p;
    const double s = in.sensitivity_v_per_dps.value_or(1.0);
    const std::string unit = in.sensitivity_v_per_dps ? "deg/s" : "V";
    const double n = Finite0(in.arw_v_rthz) / s, b = Finite0(in.bias_v) / s,
                 k = Finite0(in.rrw_v_rts) / s;
    const std::string id = in.sensor_id, name = id + "_allan";
    std::ostringstream dat;
    dat << "# sensor " << id << ": overlapping Allan deviation [" << unit
        << "] of the still, thermally quiet stretches\n"
        << "# tau_s adev adev_lo adev_hi fit arw_line bias_line rrw_line\n";
    for (size_t i = 0; i < in.tau_s.size(); ++i) {
        const double t = in.tau_s[i];
        auto at = [&](const std::vector<double>& v) { return i < v.size() ? v[i] / s : NAN; };
        dat << Num(t) << " " << Num(at(in.adev_v)) << " " << Num(at(in.adev_lo_v)) << " "
            << Num(at(in.adev_hi_v)) << " " << Num(std::sqrt(n * n / t + b * b + k * k * t / 3.0))
            << " " << Num(n > 0 ? n / std::sqrt(t) : NAN) << " " << Num(b > 0 ? b : NAN) << " "
            << Num(k > 0 ? k * std::sqrt(t / 3.0) : NAN) << "\n";
    }
    p.files.push_back({name + ".dat", dat.str()});
    const std::string d = "\"" + name + ".dat\"";
    const std::string cmd =
        "plot " + d + " using 1:2:3:4 with yerrorbars pt 7 ps 0.6 title \"measured (68 %)\", " + d +
        " using 1:5 with lines lw 2 title \"fit sqrt(N^2/tau + B^2 + K^2 tau/3)\", " + d +
        " using 1:6 with lines dt 2 title \"slope -1/2: N = " + Short(n) + " " + unit +
        "/sqrt(Hz)\", " + d + " using 1:7 with lines dt 3 title \"slope 0: B = " + Short(b) + " " +
        unit + "\", " + d + " using 1:8 with lines dt 4 title \"slope +1/2: K = " + Short(k) + " " +
        unit + "/sqrt(s)\"";
    std::ostringstream gp;
    gp << "# gyrocal analyze --plot: " << name << "\n"
       << "set datafile missing \"?\"\nset logscale xy\nset format y \"%g\"\n"
       << "set title \"" << id << ": Allan deviation (IEEE 952 terms)\" noenhanced\n"
       << "set xlabel \"tau [s]\" noenhanced\nset ylabel \"sigma_A [" << unit << "]\" noenhanced\n"
       << "set grid\nset key outside top center horizontal noenhanced\n";
    for (const char* term : {"png", "svg"}) {
        gp << (std::string(term) == "png" ? "set terminal pngcairo size 1000,600\n"
                                          : "set terminal svg size 1000,600 dynamic\n")
           << "set output \"" << name << "." << term << "\"\n" << cmd << "\n";
    }
    gp << "set output\n";
    p.files.push_back({name + ".gp", gp.str()});
    p.scripts.push_back(name + ".gp");
    p.images = {name + ".png", name + ".svg"};
    return p;
}

}  // namespace gyrocal::noise
