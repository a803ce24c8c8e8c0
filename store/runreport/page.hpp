#pragma once
// The calibration report of one run as one self-contained HTML page: inline CSS (with a print
// stylesheet), inline SVG figures, no script, no external file, no network request (a
// Content-Security-Policy forbids both). Order: header with the run's outcome and acceptance,
// contents, acceptance table, traceability, losses, processes, then one section per unit (the
// builders of sections.hpp). Pure: everything read and drawn beforehand is handed in.
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "processors/acceptance/evaluate.hpp"
#include "store/runreport/sections.hpp"
#include "store/runreport/unit_data.hpp"

namespace gyrocal::runreport {

struct ReportInput {
    db::RunDetail detail;
    std::vector<UnitData> units;
    std::vector<std::string> stems;            // figure stem of each unit (same order)
    std::map<std::string, std::string> svgs;   // figure name -> inline SVG
    std::optional<acceptance::Limits> limits;  // none: acceptance "not measured"
    std::string limits_origin, limits_problem;
    std::vector<acceptance::UnitVerdict> verdicts;  // one per unit when limits are given
    double plateau_slow_noise_dps = 0;
    std::string software_version;  // of the program writing the report
    std::string generated_utc;     // when, for the footer
    std::string database;          // the file it was read from
    std::string figures_note;      // e.g. why figures are missing ("" = all drawn)
};

std::string ReportHtml(const ReportInput& input);

}  // namespace gyrocal::runreport
