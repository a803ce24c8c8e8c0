#pragma once
// A figure as data: named tables of numbers and the series drawn from their columns, turned into
// gnuplot text. gnuplot draws; this library only writes what it reads:
//   <table>.dat   one file per table: a comment line, the column names, one row per line
//                 (missing values written "?", gnuplot's missing-value marker);
//   <figure>.gp   the script: reads the .dat files from its own directory and writes
//                 <figure>.<ext> for each terminal asked (PNG by pngcairo, SVG).
// A script starts with `reset`, so several run in one gnuplot process without leaking settings.
// Series styles: points, points with vertical error bars, lines, and a filled band between two
// columns (a confidence band). Colours are gnuplot's defaults unless a series names one.
#include <string>
#include <vector>

namespace gyrocal::plot {

struct Table {
    std::string name;                  // file stem: letters, digits, '_', '-', '.' only
    std::string comment;               // one line, written as "# comment"
    std::vector<std::string> columns;  // names, units in them (e.g. "temp_c")
    std::vector<std::vector<double>> rows;
};

enum class Style {
    kPoints,     // columns: x, y
    kErrorBars,  // columns: x, y, y_err (half-width)
    kLines,      // columns: x, y
    kBand,       // columns: x, y_low, y_high (filled, translucent)
};

struct Series {
    std::string table;
    Style style = Style::kPoints;
    std::vector<int> columns;  // 1-based column numbers in the table, as the style needs
    std::string title;         // key entry; "" = none
    std::string color;         // "" = gnuplot's next colour; else e.g. "#1f77b4"
    int dash_type = 0;         // lines: 0 solid, 2.. gnuplot's dash types
};

struct Figure {
    std::string name;  // file stem of the pictures and the script (rules of Table::name)
    std::string title, xlabel, ylabel;
    std::vector<Table> tables;
    std::vector<Series> series;  // drawn in order (draw bands first so points lie on top)
    int width_px = 1000, height_px = 600;
    bool log_x = false, log_y = false;  // logarithmic axes (e.g. an Allan deviation)
};

enum class Terminal { kPng, kSvg };
const char* Extension(Terminal t);  // "png", "svg"

// "" when the figure can be drawn; else what is wrong (naming the table/series): unsafe names,
// a series naming an unknown table, a column out of range or too few columns for its style, rows
// of the wrong width, no series.
std::string Validate(const Figure& figure);

// The text of <table>.dat.
std::string DataFileText(const Table& table);

// The text of <figure>.gp, writing one picture per terminal (in the given order).
// Precondition: Validate(figure) is "".
std::string Script(const Figure& figure, const std::vector<Terminal>& terminals);

// Every file a figure needs beside its pictures: the .dat files and the .gp script.
struct File {
    std::string name;
    std::string text;
};
std::vector<File> Files(const Figure& figure, const std::vector<Terminal>& terminals);

// `text` as a gnuplot single-quoted string literal: a quote is doubled, control characters are
// dropped. Single quotes because gnuplot runs `backquoted` text as a shell command even inside
// double quotes, and titles carry text from the database (sensor ids, verdicts) that came off
// the network.
std::string Literal(const std::string& text);

}  // namespace gyrocal::plot
