#include "store/runreport/html.hpp"

#include <cmath>

#include "lcmtypes/text/names.hpp"
#include "lcmtypes/text/number.hpp"
#include "processors/plot/svg.hpp"

namespace gyrocal::runreport::html {

namespace {

constexpr const char* kCss = R"css(
:root { --ink: #1b1f24; --muted: #59636e; --line: #d0d7de; --pass: #1a7f37; --fail: #cf222e; --ne: #9a6700; }
* { box-sizing: border-box; }
body { font: 14px/1.45 system-ui, -apple-system, "Segoe UI", Roboto, "DejaVu Sans", sans-serif; color: var(--ink);
       margin: 0 auto; max-width: 1100px; padding: 24px; }
h1 { font-size: 24px; margin: 0 0 4px; }
h2 { font-size: 19px; margin: 28px 0 8px; padding-bottom: 4px; border-bottom: 2px solid var(--line); }
h3 { font-size: 15px; margin: 18px 0 6px; }
code, .mono { font-family: "DejaVu Sans Mono", Menlo, Consolas, monospace; font-size: 12.5px; }
table { border-collapse: collapse; margin: 6px 0 12px; }
th, td { border: 1px solid var(--line); padding: 3px 8px; text-align: left; vertical-align: top; }
th { background: #f6f8fa; font-weight: 600; }
td.num { text-align: right; font-variant-numeric: tabular-nums; white-space: nowrap; }
table.kv th { width: 230px; }
table.acceptance-summary td, table.acceptance-summary th { font-size: 12.5px; }
td.pass { color: var(--pass); font-weight: 600; } td.fail { color: var(--fail); font-weight: 700; }
td.ne { color: var(--ne); font-weight: 600; }
.badge { display: inline-block; padding: 1px 10px; border-radius: 10px; font-weight: 700; color: #fff; }
.badge.pass { background: var(--pass); } .badge.fail { background: var(--fail); } .badge.ne { background: var(--ne); }
.muted, .note { color: var(--muted); }
p.not-measured { color: var(--muted); font-style: italic; margin: 4px 0 10px; }
nav ul { columns: 3; margin: 4px 0; }
.figures { display: grid; grid-template-columns: 1fr 1fr; gap: 10px; }
.figures figure { margin: 0; border: 1px solid var(--line); padding: 4px; }
svg.figure { width: 100%; height: auto; display: block; }
section.unit { border-top: 4px solid var(--line); margin-top: 32px; }
footer { margin-top: 40px; color: var(--muted); font-size: 12px; border-top: 1px solid var(--line); padding-top: 8px; }
@media (max-width: 800px) { .figures { grid-template-columns: 1fr; } nav ul { columns: 1; } }
@media print {
  @page { size: A4; margin: 14mm; }
  body { max-width: none; padding: 0; font-size: 10.5px; }
  nav { display: none; }
  h2 { break-after: avoid; }
  section.unit { break-before: page; border-top: none; }
  figure, table, .kv { break-inside: avoid; }
  .figures { grid-template-columns: 1fr 1fr; }
  .badge { border: 1px solid #000; color: #000 !important; background: none !important; }
  a { color: inherit; text-decoration: none; }
}
)css";

}  // namespace

std::string Esc(const std::string& text) { return plot::XmlEscape(text); }

Cell Text(const std::string& text, const std::string& cls) { return {Esc(text), cls, ""}; }
Cell Number(double v, const char* format) { return {text::PrintfOrDash(format, v), "num", ""}; }

Table::Table(std::vector<std::string> headers, std::string css_class)
    : headers_(std::move(headers)), css_class_(std::move(css_class)) {}

void Table::Row(std::vector<Cell> cells, const std::string& attrs) {
    std::string r = "<tr" + (attrs.empty() ? "" : " " + attrs) + ">";
    for (const Cell& c : cells)
        r += "<td" + (c.cls.empty() ? "" : " class=\"" + c.cls + "\"") +
             (c.attrs.empty() ? "" : " " + c.attrs) + ">" + c.html + "</td>";
    rows_.push_back(r + "</tr>");
}

std::string Table::str() const {
    std::string s =
        "<table" + (css_class_.empty() ? "" : " class=\"" + css_class_ + "\"") + "><thead><tr>";
    for (const std::string& h : headers_) s += "<th>" + Esc(h) + "</th>";
    s += "</tr></thead><tbody>";
    for (const std::string& r : rows_) s += r;
    return s + "</tbody></table>\n";
}

std::string KeyValues(const std::vector<std::pair<std::string, std::string>>& items,
                      const std::string& css_class) {
    std::string s = "<table class=\"" + css_class + "\"><tbody>";
    for (const auto& [k, v] : items) s += "<tr><th>" + Esc(k) + "</th><td>" + Esc(v) + "</td></tr>";
    return s + "</tbody></table>\n";
}

std::string OutcomeClass(acceptance::Outcome o) {
    using acceptance::Outcome;
    static constexpr text::NameTable<Outcome, 3> kClasses{
        {{Outcome::kPass, "pass"}, {Outcome::kFail, "fail"}, {Outcome::kNotEvaluated, "ne"}}};
    return text::NameOf(kClasses, o, "ne");
}

std::string Badge(acceptance::Outcome o) {
    return "<span class=\"badge " + OutcomeClass(o) + "\">" + Esc(acceptance::ToString(o)) +
           "</span>";
}

std::string NotMeasured(const std::string& how) {
    return "<p class=\"not-measured\">Not measured in this run" +
           (how.empty() ? "" : " (" + Esc(how) + ")") + ".</p>\n";
}

std::string Page(const std::string& title, const std::string& body, const std::string& generator) {
    return "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
           "<meta http-equiv=\"Content-Security-Policy\" content=\"default-src 'none'; style-src "
           "'unsafe-inline'; "
           "img-src data:\">\n"
           "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n"
           "<meta name=\"generator\" content=\"" +
           Esc(generator) + "\">\n<title>" + Esc(title) + "</title>\n<style>" + kCss +
           "</style>\n</head>\n<body>\n" + body + "</body>\n</html>\n";
}

}  // namespace gyrocal::runreport::html
