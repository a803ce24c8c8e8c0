#pragma once
// `gyrocal report`'s work: reads a run through the store's query library (ShowRun: plateaus,
// turns, coefficient sets, analyses, losses, processes), judges it against acceptance limits
// (given, else stored with the run), draws the figures with gnuplot, and writes the page
// (page.hpp) as <out_dir>/report-<run id>.html. Touches SQLite (read-only), gnuplot and one file.
#include <optional>
#include <string>
#include <vector>

#include "processors/acceptance/limits.hpp"
#include "store/runreport/unit_data.hpp"

namespace gyrocal::runreport {

struct ReportOptions {
    std::string db = "gyrocal.db";
    std::string run_id;
    std::string out_dir = ".";                 // must exist
    std::optional<acceptance::Limits> limits;  // instead of the stored ones
    std::string limits_origin;                 // where `limits` came from
    std::string gnuplot;                       // path of gnuplot (plot::gnuplot::FindOnPath)
    std::string software_version;
};

struct ReportResult {
    std::string path;  // the page written
    RunAcceptance acceptance;
    int figures = 0;
};

// "report-<run id>.html" with characters other than letters, digits, '.', '_', '-' made '_'.
std::string ReportFileName(const std::string& run_id);

// Throws db::NotFound (unknown run), db::StoreError, plot::gnuplot::GnuplotError, plot::SvgError,
// or std::runtime_error naming the file when it cannot be written.
ReportResult WriteReport(const ReportOptions& options);

}  // namespace gyrocal::runreport
