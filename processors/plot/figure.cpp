#include "processors/plot/figure.hpp"

#include <cmath>
#include <sstream>

#include "lcmtypes/text/names.hpp"
#include "lcmtypes/text/number.hpp"

namespace gyrocal::plot {

namespace {

bool SafeName(const std::string& name) {
    if (name.empty() || name[0] == '.') return false;
    for (char c : name) {
        const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') ||
                        (c >= '0' && c <= '9') || c == '_' || c == '-' || c == '.';
        if (!ok) return false;
    }
    return true;
}

int ColumnsNeeded(Style s) { return s == Style::kErrorBars || s == Style::kBand ? 3 : 2; }

const Table* FindTable(const Figure& f, const std::string& name) {
    for (const Table& t : f.tables)
        if (t.name == name) return &t;
    return nullptr;
}

std::string Using(const Series& s) {
    std::string u;
    for (int c : s.columns) u += (u.empty() ? "" : ":") + std::to_string(c);
    return u;
}

// gnuplot's "with" of each style.
constexpr text::NameTable<Style, 4> kWith{
    {{Style::kPoints, "points pt 7 ps 0.6"},
     {Style::kErrorBars, "yerrorbars pt 7 ps 0.8"},
     {Style::kLines, "lines lw 2"},
     {Style::kBand, "filledcurves fs transparent solid 0.25 noborder"}}};

// One clause of the plot command.
std::string Clause(const Series& s) {
    std::string clause = Literal(s.table + ".dat") + " using " + Using(s) + " with " +
                         text::NameOf(kWith, s.style, "");
    if (s.dash_type > 0) clause += " dt " + std::to_string(s.dash_type);
    if (!s.color.empty()) clause += " lc rgb " + Literal(s.color);
    clause += s.title.empty() ? " notitle" : " title " + Literal(s.title);
    return clause;
}

}  // namespace

const char* Extension(Terminal t) { return t == Terminal::kPng ? "png" : "svg"; }

std::string Literal(const std::string& text) {
    std::string out = "'";
    for (char ch : text) {
        if (static_cast<unsigned char>(ch) < 0x20 || ch == 0x7f) continue;
        if (ch == '\'') out += '\'';
        out += ch;
    }
    return out + "'";
}

std::string Validate(const Figure& f) {
    if (!SafeName(f.name)) return "figure name '" + f.name + "' is not a plain file stem";
    if (f.series.empty()) return "figure " + f.name + " has no series";
    for (const Table& t : f.tables) {
        if (!SafeName(t.name))
            return "figure " + f.name + ": table name '" + t.name + "' is not a plain file stem";
        for (size_t i = 0; i < t.rows.size(); ++i)
            if (t.rows[i].size() != t.columns.size())
                return "figure " + f.name + ": table " + t.name + " row " + std::to_string(i + 1) +
                       " has " + std::to_string(t.rows[i].size()) + " values for " +
                       std::to_string(t.columns.size()) + " columns";
    }
    for (const Series& s : f.series) {
        const Table* t = FindTable(f, s.table);
        if (!t)
            return "figure " + f.name + ": series '" + s.title + "' names no table '" + s.table +
                   "'";
        if (static_cast<int>(s.columns.size()) != ColumnsNeeded(s.style))
            return "figure " + f.name + ": series '" + s.title + "' needs " +
                   std::to_string(ColumnsNeeded(s.style)) + " columns, has " +
                   std::to_string(s.columns.size());
        for (int c : s.columns)
            if (c < 1 || c > static_cast<int>(t->columns.size()))
                return "figure " + f.name + ": series '" + s.title + "' column " +
                       std::to_string(c) + " is not in table " + t->name + " (1.." +
                       std::to_string(t->columns.size()) + ")";
    }
    return "";
}

std::string DataFileText(const Table& t) {
    std::ostringstream s;
    if (!t.comment.empty()) s << "# " << t.comment << "\n";
    s << "#";
    for (const std::string& c : t.columns) s << " " << c;
    s << "\n";
    for (const auto& row : t.rows) {
        // "?" is gnuplot's missing-value marker (set datafile missing "?").
        for (size_t i = 0; i < row.size(); ++i)
            s << (i ? " " : "") << (std::isfinite(row[i]) ? text::Sig(row[i], 9) : "?");
        s << "\n";
    }
    return s.str();
}

std::string Script(const Figure& f, const std::vector<Terminal>& terminals) {
    std::ostringstream s;
    s << "# gyrocal figure " << f.name << "\n"
      << "reset\n"
      << "set datafile missing \"?\"\n"
      << "set title " << Literal(f.title) << " noenhanced\n"
      << "set xlabel " << Literal(f.xlabel) << " noenhanced\n"
      << "set ylabel " << Literal(f.ylabel) << " noenhanced\n"
      << "set grid\nset key outside top center horizontal noenhanced\n";
    // A margin so that no point sits on the frame; on a log axis gnuplot already widens the range
    // to whole decades, and an offset on top of that adds a decade more on each side.
    const std::string x_margin = f.log_x ? "0" : "graph 0.02";
    const std::string y_margin = f.log_y ? "0" : "graph 0.05";
    s << "set offsets " << x_margin << ", " << x_margin << ", " << y_margin << ", " << y_margin
      << "\n";
    if (f.log_x) s << "set logscale x\n";
    if (f.log_y) s << "set logscale y\nset format y \"%g\"\n";
    std::string plot = "plot ";
    for (size_t i = 0; i < f.series.size(); ++i) plot += (i ? ", " : "") + Clause(f.series[i]);
    const std::string size = std::to_string(f.width_px) + "," + std::to_string(f.height_px);
    for (Terminal t : terminals) {
        if (t == Terminal::kPng)
            s << "set terminal pngcairo size " << size << "\n";
        else
            s << "set terminal svg size " << size << " dynamic font \"sans,12\"\n";
        s << "set output " << Literal(f.name + "." + Extension(t)) << "\n" << plot << "\n";
    }
    s << "set output\n";
    return s.str();
}

std::vector<File> Files(const Figure& f, const std::vector<Terminal>& terminals) {
    std::vector<File> files;
    for (const Table& t : f.tables) files.push_back({t.name + ".dat", DataFileText(t)});
    files.push_back({f.name + ".gp", Script(f, terminals)});
    return files;
}

}  // namespace gyrocal::plot
