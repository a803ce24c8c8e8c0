#include "store/runreport/page.hpp"

#include "store/runreport/html.hpp"
#include "store/runreport/traceability.hpp"

namespace gyrocal::runreport {

namespace {

std::string Header(const ReportInput& in) {
    const db::RunInfo& r = in.detail.run;
    std::string s = "<header>\n<h1>Calibration report</h1>\n<p>Run <code data-run-id>" +
                    html::Esc(r.run_id) + "</code> &middot; " + html::Esc(OutcomeText(r)) +
                    " &middot; " + std::to_string(in.units.size()) + " unit" +
                    (in.units.size() == 1 ? "" : "s");
    if (in.limits) s += " &middot; acceptance " + html::Badge(RunOutcome(in.verdicts));
    return s + "</p>\n</header>\n";
}

std::string Contents(const ReportInput& in) {
    std::string s =
        "<nav>\n<h2>Contents</h2>\n<ul>\n<li><a href=\"#acceptance\">Acceptance</a></li>\n"
        "<li><a href=\"#traceability\">Traceability</a></li>\n<li><a href=\"#losses\">Losses per "
        "channel</a></li>\n"
        "<li><a href=\"#processes\">Processes</a></li>\n";
    for (size_t i = 0; i < in.units.size(); ++i) {
        s += "<li><a href=\"#" + in.stems[i] + "\">Unit " + html::Esc(in.units[i].sensor_id) +
             "</a>";
        if (i < in.verdicts.size())
            s += " " + html::Esc(acceptance::ToString(in.verdicts[i].outcome));
        s += "</li>\n";
    }
    return s + "</ul>\n</nav>\n";
}

}  // namespace

std::string ReportHtml(const ReportInput& in) {
    LimitsInfo li;
    li.limits = in.limits ? &*in.limits : nullptr;
    li.origin = in.limits_origin;
    li.problem = in.limits_problem;
    std::string body = Header(in) + Contents(in) + AcceptanceHtml(li, in.verdicts) +
                       TraceabilityHtml(in.detail, in.software_version) + LossesHtml(in.detail) +
                       ProcessesHtml(in.detail);
    if (!in.figures_note.empty())
        body += "<p class=\"fail\">" + html::Esc(in.figures_note) + "</p>\n";
    for (size_t i = 0; i < in.units.size(); ++i) {
        const acceptance::UnitVerdict* v = i < in.verdicts.size() ? &in.verdicts[i] : nullptr;
        UnitContext c{in.detail, in.units[i], in.stems[i], in.svgs, v, in.plateau_slow_noise_dps};
        body += UnitHtml(c);
    }
    body +=
        "<footer>Written by gyrocal report " + html::Esc(in.software_version) + " on " +
        html::Esc(in.generated_utc) + " UTC from " + html::Esc(in.database) +
        ". Self-contained: no script and no external file; figures drawn by gnuplot.</footer>\n";
    return html::Page("Calibration report: run " + in.detail.run.run_id, body,
                      "gyrocal " + in.software_version);
}

}  // namespace gyrocal::runreport
