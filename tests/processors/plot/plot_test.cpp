// The plotting path: figures checked before gnuplot sees them, data files and scripts as gnuplot
// reads them, gnuplot's SVG made fit for an HTML page, and the real gnuplot drawing.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>

#include "processors/plot/figure.hpp"
#include "processors/plot/gnuplot/gnuplot.hpp"
#include "processors/plot/svg.hpp"

namespace gyrocal::plot {
namespace {

Figure Line(const std::string& name, double slope) {
    Figure f;
    f.name = name;
    f.title = name + " \"quoted\" title";
    f.xlabel = "x [1]";
    f.ylabel = "y [1]";
    Table t{name + "_data", "a line", {"x", "y", "y_err"}, {}};
    for (int i = 0; i <= 10; ++i) t.rows.push_back({double(i), slope * i, 0.1});
    f.tables = {t};
    f.series = {{t.name, Style::kErrorBars, {1, 2, 3}, "points", "#d62728"},
                {t.name, Style::kLines, {1, 2}, "line", ""}};
    return f;
}

TEST(Figure, ProblemNamesWhatCannotBeDrawn) {
    EXPECT_EQ(Validate(Line("ok", 1)), "");
    Figure f = Line("ok", 1);
    f.series[0].table = "missing";
    EXPECT_NE(Validate(f).find("names no table 'missing'"), std::string::npos) << Validate(f);
    f = Line("ok", 1);
    f.series[0].columns = {1, 2, 4};
    EXPECT_NE(Validate(f).find("column 4 is not in table ok_data (1..3)"), std::string::npos)
        << Validate(f);
    f = Line("ok", 1);
    f.series[0].columns = {1, 2};  // error bars need three
    EXPECT_NE(Validate(f).find("needs 3 columns"), std::string::npos) << Validate(f);
    f = Line("../etc/passwd", 1);
    EXPECT_NE(Validate(f).find("not a plain file stem"), std::string::npos) << Validate(f);
    f = Line("ok", 1);
    f.tables[0].rows[3].pop_back();
    EXPECT_NE(Validate(f).find("row 4 has 2 values for 3 columns"), std::string::npos)
        << Validate(f);
    f = Line("ok", 1);
    f.series.clear();
    EXPECT_NE(Validate(f).find("no series"), std::string::npos);
}

TEST(Figure, DataFileWritesMissingValuesAsGnuplotsMarker) {
    Table t{"t", "comment", {"x", "y"}, {{1.0, NAN}, {2.5, 3.0}}};
    EXPECT_EQ(DataFileText(t), "# comment\n# x y\n1 ?\n2.5 3\n");
}

TEST(Figure, ScriptResetsReadsItsDataFileAndWritesEachTerminal) {
    const std::string s = Script(Line("fig", 1), {Terminal::kPng, Terminal::kSvg});
    EXPECT_EQ(s.find("reset"),
              s.find('\n') + 1);  // first command: several scripts share one gnuplot
    EXPECT_NE(s.find("set output 'fig.png'"), std::string::npos);
    EXPECT_NE(s.find("set output 'fig.svg'"), std::string::npos);
    EXPECT_NE(s.find("'fig_data.dat' using 1:2:3 with yerrorbars"), std::string::npos);
    EXPECT_EQ(Literal("it's \"q\" `x`\n\\"), "'it''s \"q\" `x`\\'");
}

TEST(Svg, InlineSvgPrefixesIdsAndReferencesAndDropsTheProlog) {
    const std::string in =
        "<?xml version=\"1.0\"?>\n<!DOCTYPE svg>\n<svg viewBox=\"0 0 10 "
        "10\"><title>Gnuplot</title><defs>"
        "<path id='gpPt0' d='M0,0'/><use xlink:href='#gpPt0' id=\"gpPt6\"/></defs>"
        "<g id=\"gnuplot_canvas\"><use href=\"#gpPt6\" fill=\"#d62728\"/><rect "
        "fill=\"url(#gpPt0)\"/></g></svg>";
    const std::string out = InlineSvg(in, "u1_offset", "S01 <offset>");
    EXPECT_EQ(out.rfind("<svg data-figure=\"u1_offset\"", 0), 0u) << out;
    EXPECT_EQ(out.find("<?xml"), std::string::npos);
    EXPECT_NE(out.find("id='u1_offset-gpPt0'"), std::string::npos) << out;
    EXPECT_NE(out.find("xlink:href='#u1_offset-gpPt0'"), std::string::npos) << out;
    EXPECT_NE(out.find("href=\"#u1_offset-gpPt6\""), std::string::npos) << out;
    EXPECT_NE(out.find("url(#u1_offset-gpPt0)"), std::string::npos) << out;
    EXPECT_NE(out.find("fill=\"#d62728\""), std::string::npos) << "a colour is not an id reference";
    EXPECT_NE(out.find("<title>S01 &lt;offset&gt;</title>"), std::string::npos) << out;
    EXPECT_THROW(InlineSvg("<svg><script>alert(1)</script></svg>", "x", "x"), SvgError);
    EXPECT_THROW(InlineSvg("not an svg", "x", "x"), SvgError);
}

class Gnuplot : public ::testing::Test {
protected:
    void SetUp() override {
        gnuplot_ = launch::FindOnPath("gnuplot");
        if (gnuplot_.empty())
            GTEST_SKIP()
                << "gnuplot is not installed (Debian gnuplot-nox; tools/run.sh installs it)";
    }
    std::string gnuplot_;
};

TEST_F(Gnuplot, DrawsEveryFigureInOneRunAndTheirIdsDoNotCollide) {
    const std::vector<std::string> svgs =
        gnuplot::DrawInlineSvgs(gnuplot_, {Line("a", 1), Line("b", -2)});
    ASSERT_EQ(svgs.size(), 2u);
    std::multiset<std::string> ids;
    const std::regex id_re("id=['\"]([^'\"]+)['\"]");
    for (const std::string& s : svgs) {
        EXPECT_NE(s.find("</svg>"), std::string::npos);
        EXPECT_EQ(s.find("<script"), std::string::npos);
        for (auto it = std::sregex_iterator(s.begin(), s.end(), id_re);
             it != std::sregex_iterator(); ++it)
            ids.insert((*it)[1]);
    }
    ASSERT_FALSE(ids.empty());
    for (const std::string& id : ids)
        EXPECT_EQ(ids.count(id), 1u) << "id " << id << " appears twice on the page";
    // gnuplot draws the y tic labels of each figure's range: the slope -2 line reaches -20.
    EXPECT_NE(svgs[1].find(">-20<"), std::string::npos);
    EXPECT_EQ(svgs[0].find(">-20<"), std::string::npos);
}

// Text from the database in a title is only text: gnuplot runs `...` as a shell command inside
// double quotes, never inside the single-quoted literals the scripts use.
TEST_F(Gnuplot, BackquotesInTitlesAreNotRunAsCommands) {
    const auto marker = std::filesystem::temp_directory_path() /
                        ("gyrocal_plot_injected_" + std::to_string(::getpid()));
    std::filesystem::remove(marker);
    Figure f = Line("inj", 1);
    f.title = "S01`touch " + marker.string() + "`'quote\"";
    f.series[0].title = f.title;
    const std::vector<std::string> svg = gnuplot::DrawInlineSvgs(gnuplot_, {f});
    EXPECT_FALSE(std::filesystem::exists(marker)) << "gnuplot ran a command from a title";
    EXPECT_NE(svg[0].find("S01`touch "), std::string::npos);
    std::filesystem::remove(marker);
}

TEST_F(Gnuplot, AFigureThatCannotBeDrawnOrThatGnuplotRefusesIsAnErrorNamingIt) {
    const auto dir = std::filesystem::temp_directory_path() /
                     ("gyrocal_plot_test_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    Figure bad = Line("bad", 1);
    bad.series[0].table = "nope";
    try {
        gnuplot::DrawInto(gnuplot_, dir.string(), {bad}, {Terminal::kSvg});
        FAIL() << "no error";
    } catch (const gnuplot::GnuplotError& e) {
        EXPECT_NE(std::string(e.what()).find("figure bad"), std::string::npos) << e.what();
    }
    // Every value missing: gnuplot stops ("x range is invalid"); its message and line are kept.
    Figure empty = Line("empty", 1);
    for (auto& r : empty.tables[0].rows) r[1] = NAN;
    try {
        gnuplot::DrawInto(gnuplot_, dir.string(), {empty}, {Terminal::kSvg});
        FAIL() << "no error";
    } catch (const gnuplot::GnuplotError& e) {
        EXPECT_NE(std::string(e.what()).find("gnuplot"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("\"empty.gp\" line"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("range is invalid"), std::string::npos) << e.what();
    }
    std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace gyrocal::plot
