#pragma once
// The report's sections. A unit's part is a LIST of small section builders (UnitSections()), each
// reading what it needs from the unit's data (unit_data.hpp, filled through the store's query
// library) and returning its HTML; a section whose data this run does not have says so in one
// line ("Not measured in this run"), never an empty box. A new figure of the project is a new
// builder appended to the list. Pure: structs and pre-drawn SVG in, HTML out.
#include <map>
#include <string>
#include <vector>

#include "processors/acceptance/evaluate.hpp"
#include "store/runreport/traceability.hpp"
#include "store/runreport/unit_data.hpp"

namespace gyrocal::runreport {

struct UnitContext {
    const db::RunDetail& run;
    const UnitData& unit;
    std::string stem;                                // figure-name stem of this unit (figures.hpp)
    const std::map<std::string, std::string>& svgs;  // figure name -> inline SVG
    const acceptance::UnitVerdict* verdict = nullptr;  // nullptr: no limits for this report
    double plateau_slow_noise_dps = 0;
};

struct Section {
    std::string id;  // anchor suffix, e.g. "coefficients"
    std::string title;
    std::string html;
};

using UnitSectionBuilder = Section (*)(const UnitContext&);
const std::vector<UnitSectionBuilder>& UnitSections();

// The whole <section> of a unit: its heading and every builder's section.
std::string UnitHtml(const UnitContext& context);

// Run-level parts.
struct LimitsInfo {
    const acceptance::Limits* limits = nullptr;  // nullptr: none for this report
    std::string origin;                          // where they came from
    std::string problem;                         // stored limits that could not be read
};
std::string TraceabilityHtml(const db::RunDetail& detail,
                             const std::string& software_version_of_report);
std::string AcceptanceHtml(const LimitsInfo& limits,
                           const std::vector<acceptance::UnitVerdict>& verdicts);
std::string LossesHtml(const db::RunDetail& detail);
std::string ProcessesHtml(const db::RunDetail& detail);

// Unit of a coefficient: "V/degC^2" for term dT^2 of an offset (y unit / term unit).
std::string CoeffUnit(const std::string& quantity, const std::string& term);

}  // namespace gyrocal::runreport
