#include "store/format/fleet.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>

#include "lcmtypes/text/number.hpp"
#include "store/db/model_rows.hpp"
#include "store/format/format.hpp"
#include "store/format/format_util.hpp"

namespace gyrocal::format {

using namespace detail;

namespace {

constexpr double kMadToSigma = 1.4826;  // MAD of a normal distribution x this = its sigma
const double kNaN = std::nan("");

double Median(std::vector<double> v) {
    if (v.empty()) return kNaN;
    std::sort(v.begin(), v.end());
    const size_t h = v.size() / 2;
    return v.size() % 2 ? v[h] : 0.5 * (v[h - 1] + v[h]);
}

std::vector<double> Grid(const FleetOptions& o) {
    if (!o.temps_c.empty()) return o.temps_c;
    std::vector<double> g;
    for (int t = -40; t <= 85; t += 5) g.push_back(t);
    return g;
}

// The unit's model evaluated on the grid, inside its valid range only.
std::vector<std::optional<double>> Curve(const db::ModelRow& m, const std::vector<double>& grid) {
    std::vector<std::optional<double>> out;
    for (double t : grid) {
        const bool inside = t >= m.temp_min_c - 1e-9 && t <= m.temp_max_c + 1e-9;
        const auto v = inside ? db::SteadyStateValue(m, t) : std::nullopt;
        out.push_back(v && std::isfinite(*v) ? v : std::nullopt);
    }
    return out;
}

// Median and robust spread at each grid temperature.
void Spread(FleetQuantity& q, size_t temps, size_t min_units) {
    for (size_t t = 0; t < temps; ++t) {
        std::vector<double> v;
        for (const auto& u : q.values)
            if (u[t]) v.push_back(*u[t]);
        q.n.push_back(v.size());
        if (v.size() < min_units) {
            q.median.push_back(kNaN);
            q.spread.push_back(kNaN);
            continue;
        }
        const double med = Median(v);
        std::vector<double> dev;
        for (double x : v) dev.push_back(std::fabs(x - med));
        q.median.push_back(med);
        q.spread.push_back(kMadToSigma * Median(dev));
    }
}

// z of unit u at temperature t; nullopt where there is no spread.
std::optional<double> Z(const FleetQuantity& q, size_t u, size_t t) {
    if (!q.values[u][t] || !std::isfinite(q.spread[t]) || q.spread[t] <= 0) return std::nullopt;
    return (*q.values[u][t] - q.median[t]) / q.spread[t];
}

// The unit's largest |z| (signed) with its temperature, and its mean z.
struct UnitZ {
    std::optional<double> worst;
    double at_c = 0, mean = kNaN;
};
UnitZ OfUnit(const FleetQuantity& q, size_t u, const std::vector<double>& grid) {
    UnitZ r;
    double sum = 0;
    int n = 0;
    for (size_t t = 0; t < grid.size(); ++t) {
        const auto z = Z(q, u, t);
        if (!z) continue;
        sum += *z;
        ++n;
        if (!r.worst || std::fabs(*z) > std::fabs(*r.worst)) {
            r.worst = *z;
            r.at_c = grid[t];
        }
    }
    if (n > 0) r.mean = sum / n;
    return r;
}

void Judge(FleetGroup& g, const FleetOptions& o) {
    std::map<std::string, std::vector<size_t>> by_station;
    for (size_t u = 0; u < g.units.size(); ++u) {
        by_station[g.units[u].station].push_back(u);
        for (const FleetQuantity* q : {&g.offset, &g.sensitivity}) {
            const UnitZ z = OfUnit(*q, u, g.temps_c);
            if (z.worst) g.has_spread = true;
            if (z.worst && std::fabs(*z.worst) > o.k)
                g.outside.push_back({u, q->name, *z.worst, z.at_c});
        }
    }
    std::sort(g.outside.begin(), g.outside.end(), [](const auto& a, const auto& b) {
        return std::fabs(a.worst_z) > std::fabs(b.worst_z);
    });
    for (const auto& [station, members] : by_station) {
        FleetStation s{station, members.size(), kNaN, kNaN};
        std::vector<double> off, sens;
        for (size_t u : members) {
            if (const double m = OfUnit(g.offset, u, g.temps_c).mean; std::isfinite(m))
                off.push_back(m);
            if (const double m = OfUnit(g.sensitivity, u, g.temps_c).mean; std::isfinite(m))
                sens.push_back(m);
        }
        s.offset_median_z = Median(off);
        s.sensitivity_median_z = Median(sens);
        g.stations.push_back(s);
    }
}

std::string Safe(const std::string& s) {
    std::string out;
    for (char c : s) out += std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
    return out.empty() ? "model" : out;
}

}  // namespace

std::string UnitModelOf(const std::string& config_json, const std::string& sensor_id) {
    const auto j = nlohmann::json::parse(config_json, nullptr, false);
    if (j.is_object()) {
        if (const auto m = j.find("unit_models");
            m != j.end() && m->is_object() && m->contains(sensor_id) && (*m)[sensor_id].is_string())
            return (*m)[sensor_id].get<std::string>();
        if (const auto m = j.find("unit_model"); m != j.end() && m->is_string())
            return m->get<std::string>();
        if (const auto p = j.find("preset"); p != j.end() && (p->is_string() || p->is_number()))
            return "preset " + (p->is_string() ? p->get<std::string>() : p->dump());
    }
    return "unspecified";
}

std::vector<FleetGroup> FleetSpread(std::vector<FleetUnit> units, const FleetOptions& o) {
    std::sort(units.begin(), units.end(), [](const FleetUnit& a, const FleetUnit& b) {
        return std::tie(a.model, a.station, a.sensor_id) <
               std::tie(b.model, b.station, b.sensor_id);
    });
    std::vector<FleetGroup> groups;
    const std::vector<double> grid = Grid(o);
    for (FleetUnit& u : units) {
        if (groups.empty() || groups.back().model != u.model) {
            groups.emplace_back();
            groups.back().model = u.model;
            groups.back().temps_c = grid;
            groups.back().offset.name = "offset_v";
            groups.back().sensitivity.name = "sensitivity_v_per_dps";
        }
        FleetGroup& g = groups.back();
        g.offset.values.push_back(Curve(u.set.offset, grid));
        g.sensitivity.values.push_back(Curve(u.set.sensitivity, grid));
        g.units.push_back(std::move(u));
    }
    for (FleetGroup& g : groups) {
        Spread(g.offset, grid.size(), o.min_units);
        Spread(g.sensitivity, grid.size(), o.min_units);
        Judge(g, o);
    }
    return groups;
}

std::string FleetText(const std::vector<FleetGroup>& groups, const FleetOptions& o) {
    std::ostringstream out;
    for (const FleetGroup& g : groups) {
        out << "model " << Printable(g.model) << ": " << g.units.size() << " units from "
            << g.stations.size() << " station" << (g.stations.size() == 1 ? "" : "s")
            << " (the newest coefficient set of each unit)\n";
        Table t({"TEMP_C", "UNITS", "OFFSET_MEDIAN_V", "OFFSET_SPREAD_MV", "SENS_MEDIAN_V_PER_DPS",
                 "SENS_SPREAD_PCT"});
        for (size_t i = 0; i < g.temps_c.size(); ++i) {
            const double sm = g.sensitivity.median[i];
            t.Add({text::SigOrDash(g.temps_c[i], 4), std::to_string(g.offset.n[i]),
                   text::SigOrDash(g.offset.median[i], 7),
                   text::SigOrDash(g.offset.spread[i] * 1e3, 3), text::SigOrDash(sm, 6),
                   text::SigOrDash(g.sensitivity.spread[i] / sm * 100, 3)});
        }
        out << t.str();
        if (!g.has_spread) {
            out << "no spread: fewer than " << o.min_units
                << " units at every temperature (or all alike); nothing judged\n\n";
            continue;
        }
        out << "units outside the lot's spread (|z| > " << text::SigOrDash(o.k, 3)
            << ", z = (value - median) / (1.4826 MAD)): " << g.outside.size() << "\n";
        if (!g.outside.empty()) {
            Table x({"UNIT", "STATION", "RUN", "QUANTITY", "WORST_Z", "AT_TEMP_C"});
            for (const FleetDeviation& d : g.outside) {
                const FleetUnit& u = g.units[d.unit];
                x.Add({u.sensor_id, u.station.empty() ? "-" : u.station, RunLabel(u.run_id),
                       d.quantity, text::SigOrDash(d.worst_z, 3), text::SigOrDash(d.at_temp_c, 4)});
            }
            out << x.str();
        }
        Table s({"STATION", "UNITS", "OFFSET_MEDIAN_Z", "SENS_MEDIAN_Z"});
        for (const FleetStation& st : g.stations)
            s.Add({st.station.empty() ? "(this file)" : st.station, std::to_string(st.units),
                   text::SigOrDash(st.offset_median_z, 3),
                   text::SigOrDash(st.sensitivity_median_z, 3)});
        out << "per station: median over its units of their mean z\n" << s.str() << "\n";
    }
    return out.str();
}

nlohmann::json FleetJson(const std::vector<FleetGroup>& groups, const FleetOptions& o) {
    nlohmann::json a = nlohmann::json::array();
    for (const FleetGroup& g : groups) {
        nlohmann::json grid = nlohmann::json::array(), units = nlohmann::json::array();
        for (size_t i = 0; i < g.temps_c.size(); ++i) {
            grid.push_back({{"temp_c", g.temps_c[i]},
                            {"units", g.offset.n[i]},
                            {"offset_median_v", JsonNumber(g.offset.median[i])},
                            {"offset_spread_v", JsonNumber(g.offset.spread[i])},
                            {"sensitivity_median_v_per_dps", JsonNumber(g.sensitivity.median[i])},
                            {"sensitivity_spread_v_per_dps", JsonNumber(g.sensitivity.spread[i])}});
        }
        for (const FleetUnit& u : g.units)
            units.push_back({{"sensor_id", u.sensor_id},
                             {"station", u.station},
                             {"run_id", u.run_id},
                             {"coeff_row_id", u.coeff_row_id}});
        nlohmann::json outside = nlohmann::json::array(), stations = nlohmann::json::array();
        for (const FleetDeviation& d : g.outside)
            outside.push_back({{"sensor_id", g.units[d.unit].sensor_id},
                               {"station", g.units[d.unit].station},
                               {"quantity", d.quantity},
                               {"worst_z", d.worst_z},
                               {"at_temp_c", d.at_temp_c}});
        for (const FleetStation& s : g.stations)
            stations.push_back({{"station", s.station},
                                {"units", s.units},
                                {"offset_median_z", JsonNumber(s.offset_median_z)},
                                {"sensitivity_median_z", JsonNumber(s.sensitivity_median_z)}});
        a.push_back({{"model", g.model},
                     {"k", o.k},
                     {"min_units", o.min_units},
                     {"has_spread", g.has_spread},
                     {"grid", grid},
                     {"units", units},
                     {"outside", outside},
                     {"stations", stations}});
    }
    return a;
}

namespace {

plot::Figure QuantityFigure(const FleetGroup& g, const FleetQuantity& q, const FleetOptions& o) {
    const bool offset = q.name == "offset_v";
    plot::Figure f;
    f.name = "fleet_" + Safe(g.model) + (offset ? "_offset" : "_sensitivity");
    f.title = g.model + ": " + (offset ? "offset" : "sensitivity") + " of " +
              std::to_string(g.units.size()) + " units, median +- " + text::SigOrDash(o.k, 3) +
              " x spread";
    f.xlabel = "temperature [degC]";
    f.ylabel = offset ? "offset [V]" : "sensitivity [V/(deg/s)]";
    plot::Table band{"band_" + f.name,
                     "median - k spread, median + k spread, median",
                     {"temp_c", "low", "high", "median"},
                     {}};
    for (size_t t = 0; t < g.temps_c.size(); ++t) {
        if (!std::isfinite(q.spread[t])) continue;
        band.rows.push_back({g.temps_c[t], q.median[t] - o.k * q.spread[t],
                             q.median[t] + o.k * q.spread[t], q.median[t]});
    }
    f.tables.push_back(band);
    f.series.push_back({band.name, plot::Style::kBand, {1, 2, 3}, "lot spread", "#9ecae1", 0});
    f.series.push_back({band.name, plot::Style::kLines, {1, 4}, "median", "#08519c", 2});
    for (size_t u = 0; u < g.units.size(); ++u) {
        plot::Table c{
            "u" + std::to_string(u) + "_" + f.name, g.units[u].sensor_id, {"temp_c", q.name}, {}};
        for (size_t t = 0; t < g.temps_c.size(); ++t)
            if (q.values[u][t]) c.rows.push_back({g.temps_c[t], *q.values[u][t]});
        if (c.rows.empty()) continue;
        bool out = false;
        for (const FleetDeviation& d : g.outside)
            out = out || (d.unit == u && d.quantity == q.name);
        f.tables.push_back(c);
        f.series.push_back({c.name,
                            plot::Style::kLines,
                            {1, 2},
                            out ? g.units[u].sensor_id + " (outside)" : "",
                            out ? "#d62728" : "#7f7f7f",
                            0});
    }
    return f;
}

}  // namespace

std::vector<plot::Figure> FleetFigures(const std::vector<FleetGroup>& groups,
                                       const FleetOptions& o) {
    std::vector<plot::Figure> out;
    for (const FleetGroup& g : groups) {
        out.push_back(QuantityFigure(g, g.offset, o));
        out.push_back(QuantityFigure(g, g.sensitivity, o));
    }
    return out;
}

}  // namespace gyrocal::format
