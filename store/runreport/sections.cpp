#include "store/runreport/sections.hpp"

#include <algorithm>
#include <cmath>

#include "lcmtypes/text/number.hpp"
#include "processors/model/convert.hpp"
#include "processors/model/terms.hpp"
#include "store/db/utc_text.hpp"
#include "store/runreport/html.hpp"

namespace gyrocal::runreport {

namespace {

using acceptance::Outcome;
using html::Cell;
using html::Esc;

const char* kCoeff = "%.6g";

std::string Anchor(const UnitContext& c, const std::string& id) { return c.stem + "-" + id; }

// The figures of the unit with these name suffixes, side by side; "" when none was drawn.
std::string Figures(const UnitContext& c, const std::vector<std::string>& suffixes) {
    std::string s;
    for (const std::string& suffix : suffixes) {
        const auto it = c.svgs.find(c.stem + suffix);
        if (it != c.svgs.end()) s += "<figure>" + it->second + "</figure>\n";
    }
    return s.empty() ? "" : "<div class=\"figures\">\n" + s + "</div>\n";
}

Section Acceptance(const UnitContext& c) {
    Section s{"acceptance", "Acceptance", ""};
    if (!c.verdict) {
        s.html = html::NotMeasured(
            "no acceptance limits for this run: gyrocal calibrate --limits FILE, or gyrocal "
            "report --limits FILE");
        return s;
    }
    html::Table t({"limit", "", "limit value", "measured", "unit", "outcome", "note"},
                  "acceptance");
    for (const acceptance::Check& k : c.verdict->checks) {
        const std::string op = k.kind == "max" ? "<=" : k.kind == "min" ? ">=" : "required";
        t.Row({html::Text(k.key, "mono"), html::Text(op),
               k.kind == "require" ? html::Text("") : html::Number(k.limit, "%.6g"),
               k.kind == "require" ? html::Text(k.measured_text) : html::Number(k.measured, "%.4g"),
               html::Text(k.unit),
               html::Text(acceptance::ToString(k.outcome), html::OutcomeClass(k.outcome)),
               html::Text(k.note, "note")},
              "data-key=\"" + Esc(k.key) + "\"");
    }
    s.html = "<p>Unit outcome: " + html::Badge(c.verdict->outcome) + "</p>\n" + t.str();
    return s;
}

Section Curves(const UnitContext& c) {
    Section s{"curves", "Offset and sensitivity against temperature",
              Figures(c, {"_offset", "_sens"})};
    if (s.html.empty())
        s.html = html::NotMeasured("the unit has no plateau, no turn and no coefficient set");
    else
        s.html =
            "<p class=\"note\">Error bars: a plateau's standard error combined with the run's "
            "plateau slow noise of " +
            text::PrintfOrDash("%.3g", c.plateau_slow_noise_dps) +
            " deg/s (what the fitter weighted it by); a turn's standard error. Band: the fitted "
            "curve +-2 "
            "sigma from the coefficient covariance.</p>\n" +
            s.html;
    return s;
}

Section Residuals(const UnitContext& c) {
    Section s{"residuals", "Residuals", Figures(c, {"_resid_temp", "_resid_time", "_sens_resid"})};
    if (s.html.empty()) s.html = html::NotMeasured("no coefficient set to compare the points with");
    return s;
}

std::string ModelTable(const db::ModelRow& m) {
    html::Table t({"term", "coefficient", "standard uncertainty", "unit"}, "coeffs");
    for (size_t i = 0; i < m.term_names.size(); ++i) {
        const double var =
            i < m.covariance.size() && i < m.covariance[i].size() ? m.covariance[i][i] : NAN;
        t.Row(
            {html::Text(m.term_names[i], "mono"), html::Number(m.coeffs.at(i), kCoeff),
             html::Number(std::sqrt(var), "%.2g"),
             html::Text(CoeffUnit(m.quantity, m.term_names[i]))},
            "data-quantity=\"" + Esc(m.quantity) + "\" data-term=\"" + Esc(m.term_names[i]) + "\"");
    }
    return t.str() + "<p class=\"note\">" + Esc(m.quantity) + ": method " + Esc(m.method) +
           ", T0 " + text::PrintfOrDash("%.4g", m.t0_c) + " degC, valid " +
           text::PrintfOrDash("%.4g", m.temp_min_c) + " .. " +
           text::PrintfOrDash("%.4g", m.temp_max_c) + " degC, " + std::to_string(m.n_points) +
           " points, weighted residual RMS " + text::PrintfOrDash("%.3g", m.residual_rms) +
           ", condition number " + text::PrintfOrDash("%.3g", m.condition_number) + "</p>\n";
}

std::string SetHtml(const db::CoeffSetInfo& set, const std::string& role) {
    return "<h4>" + Esc(role) + ": coefficient set " + std::to_string(set.set.coeff_set_id) +
           " (source " + Esc(set.set.source) + ", stored row " + std::to_string(set.coeff_row_id) +
           ")</h4>\n" + "<div data-coeff-row=\"" + std::to_string(set.coeff_row_id) + "\">" +
           ModelTable(set.set.offset) + ModelTable(set.set.sensitivity) + "</div>\n";
}

// What a set is, for people (model/convert.hpp names the sources).
std::string Role(const UnitContext& c, const db::CoeffSetInfo& set) {
    const bool final = c.unit.calibration && set.coeff_row_id == c.unit.calibration->coeff_row_id;
    if (set.set.source == model::kClosedLoopSource)
        return final ? "Final set (closed loop: every still sample, the terms the data confirm)"
                     : "Closed-loop set (not the final one)";
    if (c.unit.plateau_set && set.coeff_row_id == c.unit.plateau_set->coeff_row_id)
        return "Plateau set (plateau means only; the final set is fitted on every still sample)";
    return final ? "Calibration" : "Also stored";
}

Section Coefficients(const UnitContext& c) {
    Section s{"coefficients", "Coefficients", ""};
    if (c.unit.calibration) s.html += SetHtml(*c.unit.calibration, Role(c, *c.unit.calibration));
    if (c.unit.plateau_set) s.html += SetHtml(*c.unit.plateau_set, Role(c, *c.unit.plateau_set));
    for (const auto& other : c.unit.other_sets)
        if (!c.unit.plateau_set || other.coeff_row_id != c.unit.plateau_set->coeff_row_id)
            s.html += SetHtml(other, Role(c, other));
    if (s.html.empty()) s.html = html::NotMeasured("no coefficient set was stored for this unit");
    return s;
}

// In the plateau set (the calibration itself when there is no other).
bool InSet(const UnitContext& c, int64_t plateau_id) {
    const auto& set = c.unit.plateau_set ? c.unit.plateau_set : c.unit.calibration;
    if (!set) return false;
    const auto& ids = set->set.plateau_ids;
    return std::find(ids.begin(), ids.end(), plateau_id) != ids.end();
}

Section Points(const UnitContext& c) {
    Section s{"points", "Plateaus and turns", ""};
    if (c.unit.plateaus.empty() && c.unit.turns.empty()) {
        s.html = html::NotMeasured("no plateau and no turn of this unit was recorded");
        return s;
    }
    html::Table p({"plateau", "setpoint [degC]", "temp_mean_c", "slope [degC/min]", "gyro_mean_v",
                   "gyro_sem_v", "samples", "in the fit"},
                  "plateaus");
    for (const auto& r : c.unit.plateaus)
        p.Row({html::Number(static_cast<double>(r.plateau_id), "%.0f"),
               html::Number(r.setpoint_c, "%.4g"), html::Number(r.temp_mean_c, "%.3f"),
               html::Number(r.temp_slope_c_per_min, "%.2g"), html::Number(r.gyro_mean_v, "%.6f"),
               html::Number(r.gyro_sem_v, "%.2g"), html::Number(r.n_samples, "%.0f"),
               html::Text(InSet(c, r.plateau_id) ? "yes" : "no")},
              "data-plateau=\"" + std::to_string(r.plateau_id) + "\"");
    html::Table t({"turn", "direction", "temp_c", "encoder angle [deg]", "sensitivity [mV/(deg/s)]",
                   "standard error [mV/(deg/s)]", "accepted"},
                  "turns");
    for (const auto& r : c.unit.turns)
        t.Row({html::Number(static_cast<double>(r.rotation_id), "%.0f"),
               html::Number(r.direction, "%+.0f"), html::Number(r.temp_c, "%.3f"),
               html::Number(r.encoder_angle_deg, "%.4f"),
               html::Number(r.sensitivity_v_per_dps * 1e3, "%.6g"),
               html::Number(r.sensitivity_stderr_v_per_dps * 1e3, "%.2g"),
               html::Text(r.accepted ? "yes" : "no: " + r.reject_reason, r.accepted ? "" : "fail")},
              "data-turn=\"" + std::to_string(r.rotation_id) + "\"");
    s.html = (p.Empty() ? html::NotMeasured("no plateau of this unit was recorded") : p.str()) +
             (t.Empty() ? html::NotMeasured("no turn of this unit was recorded") : t.str());
    return s;
}

Section Refusals(const UnitContext& c) {
    Section s{"refusals", "Outliers and refusals", ""};
    std::string items;
    for (const auto& r : c.unit.turns)
        if (!r.accepted)
            items += "<li>turn " + std::to_string(r.rotation_id) + " at " +
                     text::PrintfOrDash("%.2f", r.temp_c) +
                     " degC refused by the rotation estimator: " + Esc(r.reject_reason) + "</li>\n";
    for (const auto& p : c.unit.plateaus)
        if (c.unit.calibration && !InSet(c, p.plateau_id))
            items += "<li>plateau " + std::to_string(p.plateau_id) + " at " +
                     text::PrintfOrDash("%.2f", p.temp_mean_c) +
                     " degC is not in the plateau set</li>\n";
    if (!c.unit.analyses.empty()) {
        const auto j = nlohmann::json::parse(c.unit.analyses.back().result_json, nullptr, false);
        if (j.is_object() && j.contains("could_not_test") && j["could_not_test"].is_array())
            for (const auto& w : j["could_not_test"])
                if (w.is_string())
                    items +=
                        "<li>analysis could not test: " + Esc(w.get<std::string>()) + "</li>\n";
    }
    s.html = items.empty() ? "<p>None: every plateau and turn of this unit was used.</p>\n"
                           : "<ul>\n" + items + "</ul>\n";
    return s;
}

std::string CandidatesTable(const nlohmann::json& cands) {
    html::Table t({"effect", "term", "decision", "z2", "CV gain", "note"}, "candidates");
    for (const auto& k : cands) {
        const auto num = [&](const char* key) -> double {
            return k.contains(key) && k[key].is_number() ? k[key].get<double>() : NAN;
        };
        t.Row({html::Text(k.value("effect", "")), html::Text(k.value("term", ""), "mono"),
               html::Text(k.value("decision", "")), html::Number(num("statistic"), "%.3g"),
               html::Number(num("cv_gain"), "%.3g"), html::Text(k.value("note", ""), "note")});
    }
    return t.Empty() ? "" : "<h4>Candidates tested</h4>\n" + t.str();
}

Section Analysis(const UnitContext& c) {
    Section s{"analysis", "Closed-loop analysis", ""};
    if (c.unit.analyses.empty()) {
        s.html = html::NotMeasured("no analysis: gyrocal analyze " + c.run.run.run_id);
        return s;
    }
    // The analysis that made the final set (the calibration's closed loop), else the newest.
    const db::AnalysisRow& a =
        c.unit.final_analysis ? *c.unit.final_analysis : c.unit.analyses.back();
    const auto j = nlohmann::json::parse(a.result_json, nullptr, false);
    const auto expected = [&](const char* key) -> double {
        if (!j.is_object() || !j.contains("expected_after") || !j["expected_after"].contains(key))
            return NAN;
        const auto& v = j["expected_after"][key];
        return v.is_number() ? v.get<double>() : NAN;
    };
    s.html = "<p>Analysis " + std::to_string(a.analysis_id) + " (" +
             Esc(db::UtcText(a.created_wall_utime)) + " UTC, " + Esc(a.software_version) +
             "): outcome <strong data-outcome>" +
             Esc(a.outcome.value_or("not stored (an analysis older than outcomes)")) +
             "</strong>, verdict <strong data-verdict>" + Esc(a.verdict) + "</strong></p>\n";
    html::Table t({"figure", "before (declared model)", "after (extended model)", "floor",
                   "expected after (fit)"},
                  "analysis");
    t.Row({html::Text("offset RMS [mV]"), html::Number(a.offset_rms_v_before * 1e3, "%.4g"),
           html::Number(a.offset_rms_v_after * 1e3, "%.4g"), html::Text(""),
           html::Number(expected("offset_rms_v") * 1e3, "%.4g")});
    t.Row({html::Text("rate RMS [deg/s]"), html::Number(a.rate_rms_dps_before, "%.4g"),
           html::Number(a.rate_rms_dps_after, "%.4g"), html::Number(a.floor_rate_rms_dps, "%.4g"),
           html::Number(expected("rate_rms_dps"), "%.4g")});
    t.Row({html::Text("drift [deg/h]"), html::Number(a.drift_dph_before, "%.4g"),
           html::Number(a.drift_dph_after, "%.4g"), html::Text(""), html::Text("")});
    s.html += t.str() +
              "<p class=\"note\">On held-out still data (blocks of the run the fit did not see): "
              "before = the declared model, after = with the terms the data confirmed" +
              (c.unit.final_analysis ? std::string(" (the final set)") : std::string()) +
              "; floor: the white scatter of a 10 s bin, what a perfect model also leaves.</p>\n" +
              Figures(c, {"_loop_resid_time", "_loop_resid_temp"});
    const auto added = nlohmann::json::parse(a.added_json, nullptr, false);
    if (added.is_array() && !added.empty()) {
        html::Table e({"effect", "term", "coefficient", "standard uncertainty", "unit"}, "added");
        for (const auto& x : added) {
            const auto num = [&](const char* k) -> double {
                return x.contains(k) && x[k].is_number() ? x[k].get<double>() : NAN;
            };
            e.Row({html::Text(x.value("effect", "")), html::Text(x.value("term", ""), "mono"),
                   html::Number(num("coefficient"), kCoeff), html::Number(num("stderr"), "%.2g"),
                   html::Text(x.value("unit", ""))});
        }
        s.html += "<h4>Effects added</h4>\n" + e.str();
    }
    const auto cands = nlohmann::json::parse(a.candidates_json, nullptr, false);
    if (cands.is_array()) s.html += CandidatesTable(cands);
    return s;
}

// Figures the project does not measure per run yet: one line each until they are wired in.
Section Allan(const UnitContext&) { return {"allan", "Allan deviation", html::NotMeasured()}; }
Section Repeatability(const UnitContext&) {
    return {"repeatability", "Repeatability", html::NotMeasured()};
}
Section Validation(const UnitContext&) {
    return {"validation", "Error of the model on another run", html::NotMeasured()};
}

}  // namespace

const std::vector<UnitSectionBuilder>& UnitSections() {
    static const std::vector<UnitSectionBuilder> builders = {
        Acceptance, Curves,   Residuals, Coefficients,  Points,
        Refusals,   Analysis, Allan,     Repeatability, Validation};
    return builders;
}

std::string UnitHtml(const UnitContext& c) {
    std::string s = "<section class=\"unit\" id=\"" + c.stem + "\" data-sensor=\"" +
                    Esc(c.unit.sensor_id) + "\">\n<h2>Unit " + Esc(c.unit.sensor_id) +
                    (c.verdict ? " " + html::Badge(c.verdict->outcome) : "") + "</h2>\n";
    for (UnitSectionBuilder build : UnitSections()) {
        const Section sec = build(c);
        s += "<div class=\"part\" id=\"" + Anchor(c, sec.id) + "\" data-part=\"" + sec.id +
             "\">\n<h3>" + Esc(sec.title) + "</h3>\n" + sec.html + "</div>\n";
    }
    return s + "</section>\n";
}

std::string CoeffUnit(const std::string& quantity, const std::string& term) {
    const std::string y = quantity == "offset_v"                ? "V"
                          : quantity == "sensitivity_v_per_dps" ? "V/(deg/s)"
                                                                : "?";
    model::ResolvedTerm r;
    std::string error;
    if (!model::ResolveTerm(term, &r, &error)) return "?";
    const std::string u(r.def->unit);
    if (u == "1") return y;
    const bool compound = u.find('/') != std::string::npos;
    return (y.find('/') != std::string::npos ? "(" + y + ")" : y) + "/" +
           (compound ? "(" + u + ")" : u);
}

std::string TraceabilityHtml(const db::RunDetail& d, const std::string& version) {
    const db::RunInfo& r = d.run;
    std::vector<std::pair<std::string, std::string>> kv = {
        {"run id", r.run_id},
        {"outcome", OutcomeText(r)},
        {"software version (run)",
         r.software_version.empty() ? "not recorded" : r.software_version},
        {"software version (recorder)",
         r.recorder_version.empty() ? "not recorded" : r.recorder_version},
        {"software version (this report)", version},
        {"command line", r.command_line.empty() ? "not recorded" : r.command_line},
        {"started (producer clock, utime)",
         r.started_utime ? std::to_string(*r.started_utime) : "-"},
        {"stopped (producer clock, utime)",
         r.stopped_utime ? std::to_string(*r.stopped_utime) : "-"},
        {"length (producer clock)",
         r.started_utime && r.stopped_utime
             ? text::PrintfOrDash("%.3g", (*r.stopped_utime - *r.started_utime) / 3.6e9) + " h"
             : "-"},
        {"first seen by the recorder (UTC)", db::UtcText(r.first_recv_utime)},
        {"sensors",
         [&] {
             std::string s;
             for (const auto& id : r.sensor_ids) s += (s.empty() ? "" : ", ") + id;
             return s.empty() ? std::string("none declared") : s;
         }()},
        {"recorded",
         std::to_string(r.gyro_samples) + " gyro samples, " + std::to_string(r.encoder_samples) +
             " encoder samples, " + std::to_string(r.chamber_states) + " chamber states, " +
             std::to_string(r.plateaus) + " plateaus, " + std::to_string(r.sensitivity_points) +
             " turns, " + std::to_string(r.coeff_sets) + " coefficient sets"},
    };
    const DataSource src = SourceOf(r);
    std::vector<std::pair<std::string, std::string>> source = {{"kind", src.kind}};
    source.insert(source.end(), src.details.begin(), src.details.end());
    std::string hosts;
    for (const auto& [host, what] : Hosts(d))
        hosts += "<li><code>" + Esc(host) + "</code>: " + Esc(what) + "</li>";
    return "<section id=\"traceability\">\n<h2>Traceability</h2>\n" + html::KeyValues(kv) +
           "<h3>Source of the data</h3>\n" + html::KeyValues(source, "kv source") +
           "<h3>Hosts</h3>\n" +
           (hosts.empty() ? "<p>none recorded</p>\n" : "<ul class=\"hosts\">" + hosts + "</ul>\n") +
           "</section>\n";
}

std::string AcceptanceHtml(const LimitsInfo& l,
                           const std::vector<acceptance::UnitVerdict>& verdicts) {
    std::string s = "<section id=\"acceptance\">\n<h2>Acceptance</h2>\n";
    if (!l.problem.empty())
        s += "<p class=\"fail\">Stored limits cannot be read: " + Esc(l.problem) + "</p>\n";
    if (!l.limits) {
        return s +
               html::NotMeasured(
                   "no acceptance limits for this run: gyrocal calibrate --limits FILE, or gyrocal "
                   "report --limits FILE") +
               "</section>\n";
    }
    s += "<p>Limits " + Esc(l.origin) +
         (l.limits->description.empty() ? "" : ": " + Esc(l.limits->description)) + "</p>\n";
    // One row per unit, one column per limit (the limit's name may break after each '_').
    std::string head = "<tr><th>unit</th><th>outcome</th>";
    std::vector<std::string> keys;
    const std::vector<acceptance::Check> none;
    for (const auto& c : verdicts.empty() ? none : verdicts.front().checks) {
        keys.push_back(c.key);
        std::string name = Esc(c.key);
        for (size_t at = name.find('_'); at != std::string::npos; at = name.find('_', at + 6))
            name.insert(at + 1, "<wbr>");
        const std::string op = c.kind == "max" ? "&lt;= " : c.kind == "min" ? "&gt;= " : "required";
        head +=
            "<th>" + name + "<br><span class=\"muted\">" + op +
            (c.kind == "require" ? "" : text::PrintfOrDash("%.6g", c.limit) + " " + Esc(c.unit)) +
            "</span></th>";
    }
    std::string rows;
    for (const auto& v : verdicts) {
        rows += "<tr data-sensor=\"" + Esc(v.sensor_id) + "\" data-outcome=\"" +
                Esc(acceptance::ToString(v.outcome)) + "\"><td class=\"mono\">" + Esc(v.sensor_id) +
                "</td><td class=\"" + html::OutcomeClass(v.outcome) + "\">" +
                Esc(acceptance::ToString(v.outcome)) + "</td>";
        for (const auto& c : v.checks) {
            const std::string shown =
                c.kind == "require" ? c.measured_text : text::PrintfOrDash("%.4g", c.measured);
            rows += "<td class=\"" + html::OutcomeClass(c.outcome) + "\" data-key=\"" + Esc(c.key) +
                    "\">" + Esc(shown) + "<br>" + Esc(acceptance::ToString(c.outcome)) + "</td>";
        }
        rows += "</tr>";
    }
    s += "<table class=\"acceptance-summary\"><thead>" + head + "</tr></thead><tbody>" + rows +
         "</tbody></table>\n";
    html::Table defs({"limit", "unit", "what is measured"}, "limit-defs");
    for (const acceptance::LimitDef& d : acceptance::LimitDefs())
        if (std::find(keys.begin(), keys.end(), d.key) != keys.end())
            defs.Row({html::Text(std::string(d.key), "mono"), html::Text(std::string(d.unit)),
                      html::Text(std::string(d.meaning))});
    return s + defs.str() + "</section>\n";
}

std::string LossesHtml(const db::RunDetail& d) {
    std::string s = "<section id=\"losses\">\n<h2>Losses per channel</h2>\n";
    if (d.losses.empty())
        return s +
               "<p>None recorded: the recorder saw no sequence gap, decode error or queue "
               "drop.</p>\n</section>\n";
    html::Table t({"channel", "seq_gaps", "seq_backwards", "decode_errors", "queue_drops"},
                  "losses");
    for (const auto& l : d.losses)
        t.Row({html::Text(l.channel.empty() ? "(recorder)" : l.channel, "mono"),
               html::Number(l.seq_gaps, "%.0f"), html::Number(l.seq_backwards, "%.0f"),
               html::Number(l.decode_errors, "%.0f"), html::Number(l.queue_drops, "%.0f")},
              "data-channel=\"" + Esc(l.channel) + "\"");
    return s + t.str() + "</section>\n";
}

std::string ProcessesHtml(const db::RunDetail& d) {
    std::string s =
        "<section id=\"processes\">\n<h2>Processes</h2>\n<p class=\"note\">The last STATUS of each "
        "process in "
        "this run: its own count of what it received, lost and refused.</p>\n";
    if (d.processes.empty()) return s + "<p>None recorded.</p>\n</section>\n";
    html::Table t({"process", "host", "pid", "state", "received", "published", "decode errors",
                   "seq gaps", "queue drops", "refused", "last refusal"},
                  "processes");
    for (const auto& p : d.processes)
        t.Row({html::Text(p.process, "mono"), html::Text(p.host, "mono"),
               html::Number(p.pid, "%.0f"), html::Text(p.state),
               html::Number(static_cast<double>(p.received), "%.0f"),
               html::Number(static_cast<double>(p.published), "%.0f"),
               html::Number(static_cast<double>(p.decode_errors), "%.0f"),
               html::Number(static_cast<double>(p.seq_gaps), "%.0f"),
               html::Number(static_cast<double>(p.queue_drops), "%.0f"),
               html::Number(static_cast<double>(p.rejected), "%.0f"),
               html::Text(p.last_reject, "note")});
    return s + t.str() + "</section>\n";
}

}  // namespace gyrocal::runreport
