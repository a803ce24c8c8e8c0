#pragma once
// Small HTML building blocks for the report: escaping (every string from the database came off
// the network and is escaped), tables, key-value lists, outcome badges, number formats, and the
// page around the body (inline CSS with a print stylesheet; a Content-Security-Policy that allows
// no script and no network request, so the file is the whole report, offline). Pure.
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "processors/acceptance/evaluate.hpp"

namespace gyrocal::runreport::html {

std::string Esc(const std::string& text);

// printf-style number ("%.6g" ...); "-" when not finite.
struct Cell {
    std::string html;   // already HTML
    std::string cls;    // CSS class ("num", "pass", ...)
    std::string attrs;  // extra attributes, already HTML (e.g. data-key="...")
};
Cell Text(const std::string& text, const std::string& cls = "");
Cell Number(double v, const char* format = "%.6g");

class Table {
public:
    explicit Table(std::vector<std::string> headers, std::string css_class = "");
    // `attrs`: extra attributes of the <tr>, already HTML.
    void Row(std::vector<Cell> cells, const std::string& attrs = "");
    bool Empty() const { return rows_.empty(); }
    std::string str() const;

private:
    std::vector<std::string> headers_;
    std::string css_class_;
    std::vector<std::string> rows_;
};

// A two-column table of labels and plain-text values.
std::string KeyValues(const std::vector<std::pair<std::string, std::string>>& items,
                      const std::string& css_class = "kv");

// <span class="badge pass|fail|ne">pass|FAIL|not evaluated</span>
std::string Badge(acceptance::Outcome outcome);
std::string OutcomeClass(acceptance::Outcome outcome);  // "pass", "fail", "ne"

// The one line of a section whose data this run does not have.
std::string NotMeasured(const std::string& how_to_get_it = "");

// The whole page. `title` is text; `body` is HTML.
std::string Page(const std::string& title, const std::string& body, const std::string& generator);

}  // namespace gyrocal::runreport::html
