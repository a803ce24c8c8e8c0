#include "store/runreport/build.hpp"

#include <chrono>
#include <filesystem>
#include <fstream>

#include "processors/plot/gnuplot/gnuplot.hpp"
#include "store/db/central_url.hpp"
#include "store/db/utc_text.hpp"
#include "store/runreport/figures.hpp"
#include "store/runreport/html.hpp"
#include "store/runreport/page.hpp"

namespace gyrocal::runreport {

std::string ReportFileName(const std::string& run_id) {
    std::string safe = run_id.empty() ? "no-run" : run_id;
    for (char& c : safe) {
        const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') ||
                        (c >= '0' && c <= '9') || c == '.' || c == '_' || c == '-';
        if (!ok) c = '_';
    }
    return "report-" + safe + ".html";
}

ReportResult WriteReport(const ReportOptions& o) {
    auto db = db::OpenForQuery(o.db);
    ReportInput in;
    in.detail = db::ShowRun(*db, o.run_id);
    db.reset();
    in.units = Units(in.detail);
    in.plateau_slow_noise_dps = PlateauSlowNoiseDps(in.detail.run);
    ReportResult result;
    result.acceptance = AcceptRun(in.detail, o.limits, o.limits_origin);
    in.limits = result.acceptance.limits.limits;
    in.limits_origin = result.acceptance.limits.origin;
    in.limits_problem = result.acceptance.limits.problem;
    in.verdicts = result.acceptance.verdicts;

    const int64_t t0 = TimeOrigin(in.detail);
    std::vector<plot::Figure> figures;
    for (size_t i = 0; i < in.units.size(); ++i) {
        in.stems.push_back("u" + std::to_string(i + 1));
        for (plot::Figure& f :
             UnitFigures(in.units[i], in.stems.back(), in.plateau_slow_noise_dps, t0))
            figures.push_back(std::move(f));
    }
    const std::vector<std::string> svgs = plot::gnuplot::DrawInlineSvgs(o.gnuplot, figures);
    for (size_t i = 0; i < figures.size(); ++i) in.svgs[figures[i].name] = svgs[i];
    result.figures = static_cast<int>(figures.size());

    in.software_version = o.software_version;
    in.database = db::WithoutCredentials(o.db);
    const int64_t now_us = db::WallUtimeNow();
    in.generated_utc = db::UtcText(now_us);
    const std::string page = ReportHtml(in);

    const std::filesystem::path path = std::filesystem::path(o.out_dir) / ReportFileName(o.run_id);
    const std::filesystem::path tmp = path.string() + ".tmp";
    {
        std::ofstream f(tmp, std::ios::binary | std::ios::trunc);
        f << page;
        if (!f.flush()) throw std::runtime_error("cannot write " + tmp.string());
    }
    std::error_code ec;
    std::filesystem::rename(tmp, path, ec);  // a reader never sees half a page
    if (ec) throw std::runtime_error("cannot write " + path.string() + ": " + ec.message());
    result.path = path.string();
    return result;
}

}  // namespace gyrocal::runreport
