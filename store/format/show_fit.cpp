#include "store/format/show_fit.hpp"

#include <cmath>
#include <sstream>

#include "lcmtypes/text/number.hpp"
#include "store/format/format.hpp"
#include "store/format/format_util.hpp"

namespace gyrocal::format {

using namespace detail;

namespace {

std::string PlusMinus(double v, double se, int precision) {
    return text::SigOrDash(v, precision) + " +- " + text::SigOrDash(se, 2);
}

std::string Approach(int a) { return a > 0 ? "from colder" : a < 0 ? "from hotter" : "run start"; }

void ReportBlock(std::ostringstream& out, const db::FitReportRow& r) {
    out << "  " << Printable(r.sensor_id) << " (" << Printable(r.source) << ", set "
        << (r.coeff_set_id < 0 ? std::string("none") : std::to_string(r.coeff_set_id))
        << (r.is_final ? ", final" : ", not final: the run's stop made no report") << "): ";
    out << (r.status == "complete" ? "COMPLETE" : r.status == "partial" ? "PARTIAL" : "NONE");
    if (!r.reason.empty()) out << " - " << Printable(r.reason);
    out << "\n    slow noise added to each plateau: " << text::SigOrDash(r.slow_noise_dps, 3)
        << " deg/s (" << text::SigOrDash(r.slow_noise_v, 3) << " V), from "
        << Printable(r.slow_noise_source) << "\n";
    for (const db::FitExclusionRow& e : r.excluded)
        out << "    EXCLUDED " << Printable(e.kind) << " " << e.item_id << " at "
            << text::PrintfOrDash("%.2f", e.temp_c) << " C: " << Printable(e.reason) << "\n";
    out << "    offset: " << Printable(r.offset_detail) << "\n";
    out << "    sensitivity: " << Printable(r.sensitivity_detail) << "\n";
}

std::string RepeatabilityText(const db::RunDetail& d) {
    Table t({"SENSOR", "TEMP_C", "FIRST_PLATEAU", "SECOND_PLATEAU", "APPROACHES", "OFFSET_DIFF_MV",
             "OFFSET_DIFF_DPS", "Z", "VERDICT"});
    int n = 0;
    for (const db::FitReportInfo& f : d.fit_reports)
        for (const db::RepeatabilityRow& r : f.report.repeats) {
            ++n;
            t.Add({f.report.sensor_id, text::PrintfOrDash("%.2f", r.temp_c),
                   std::to_string(r.first_plateau_id), std::to_string(r.second_plateau_id),
                   Approach(r.first_approach) + ", " + Approach(r.second_approach),
                   PlusMinus(1e3 * r.offset_diff_v, 1e3 * r.offset_diff_stderr_v, 3),
                   PlusMinus(r.offset_diff_dps, r.offset_diff_stderr_dps, 3),
                   text::SigOrDash(r.z, 3), r.verdict});
        }
    if (n == 0) return "  none: no temperature was visited twice\n";
    return t.str() +
           "  (second visit minus first, the fitted model's step between their temperatures "
           "taken out; +- 1 sigma of both plateaus' errors)\n";
}

std::string NoiseText(const db::RunDetail& d) {
    if (d.noise.empty()) return "  none recorded\n";
    Table t({"SENSOR", "STILL_S", "SEGMENTS", "LONGEST_S", "ARW_DPS_RTHZ", "BIAS_INSTAB_DPS",
             "RRW_DPS_RTS", "ARW_V_RTHZ", "BIAS_INSTAB_V", "RRW_V_RTS"});
    std::string notes;
    for (const db::NoiseInfo& ni : d.noise) {
        const db::NoiseRow& n = ni.noise;
        const double s = ni.sensitivity_v_per_dps.value_or(NAN);
        t.Add({n.sensor_id, text::SigOrDash(n.still_s, 5), std::to_string(n.n_segments),
               text::SigOrDash(n.longest_segment_s, 4),
               PlusMinus(n.arw_v_rthz / s, n.arw_stderr_v_rthz / s, 3),
               PlusMinus(n.bias_instability_v / s, n.bias_instability_stderr_v / s, 3),
               PlusMinus(n.rrw_v_rts / s, n.rrw_stderr_v_rts / s, 3),
               text::SigOrDash(n.arw_v_rthz, 3), text::SigOrDash(n.bias_instability_v, 3),
               text::SigOrDash(n.rrw_v_rts, 3)});
        if (!n.fit_note.empty())
            notes += "  " + Printable(n.sensor_id) + ": " + Printable(n.fit_note) + "\n";
    }
    return t.str() + notes +
           "  (overlapping Allan deviation of the still, thermally quiet stretches; sigma_A^2 = "
           "N^2/tau "
           "+ B^2 + K^2 tau/3; deg/s through the sensitivity at T0 of the run's fitter set; "
           "gyrocal analyze RUN --plot draws it)\n";
}

}  // namespace

std::string SetStatusLabel(const db::RunDetail& d, const db::CoeffSetInfo& c) {
    for (const db::FitReportInfo& f : d.fit_reports) {
        const db::FitReportRow& r = f.report;
        if (r.sensor_id != c.set.sensor_id || r.source != c.set.source ||
            r.coeff_set_id != c.set.coeff_set_id)
            continue;
        if (r.status == "complete")
            return std::string("  COMPLETE") + (r.is_final ? ", final" : "");
        return "  PARTIAL" + std::string(r.is_final ? ", final" : "") + ": " + Printable(r.reason);
    }
    return "";
}

std::string FitSectionsText(const db::RunDetail& d) {
    std::ostringstream out;
    out << "\nFit reports (final of each sensor and source: " << d.fit_reports.size() << ")\n";
    if (d.fit_reports.empty()) out << "  none recorded\n";
    for (const db::FitReportInfo& f : d.fit_reports) ReportBlock(out, f.report);
    out << "\nRepeatability (temperatures the run visited again)\n" << RepeatabilityText(d);
    out << "\nNoise (Allan deviation per unit)\n" << NoiseText(d);
    return out.str();
}

void AddFitJson(nlohmann::json& j, const db::RunDetail& d) {
    nlohmann::json reports = nlohmann::json::array();
    for (const db::FitReportInfo& f : d.fit_reports) {
        const db::FitReportRow& r = f.report;
        nlohmann::json excluded = nlohmann::json::array(), repeats = nlohmann::json::array();
        for (const db::FitExclusionRow& e : r.excluded)
            excluded.push_back(GYROCAL_JSON_FIELDS(e, kind, item_id, temp_c, value, residual,
                                                   residual_sigma, statistic, threshold, reason));
        for (const db::RepeatabilityRow& x : r.repeats)
            repeats.push_back(GYROCAL_JSON_FIELDS(x, temp_c, first_plateau_id, second_plateau_id,
                                                  first_approach, second_approach, offset_diff_v,
                                                  offset_diff_stderr_v, offset_diff_dps,
                                                  offset_diff_stderr_dps, z, verdict));
        nlohmann::json report = GYROCAL_JSON_FIELDS(
            r, sensor_id, source, coeff_set_id, is_final, status, reason, offset_detail,
            sensitivity_detail, slow_noise_v, slow_noise_dps, slow_noise_source);
        report["excluded"] = excluded;
        report["repeatability"] = repeats;
        reports.push_back(report);
    }
    j["fit_reports"] = reports;
    nlohmann::json noise = nlohmann::json::array();
    for (const db::NoiseInfo& ni : d.noise) {
        const db::NoiseRow& n = ni.noise;
        nlohmann::json adev = nlohmann::json::array();
        for (size_t i = 0; i < n.tau_s.size(); ++i)
            adev.push_back({{"tau_s", n.tau_s[i]},
                            {"adev_v", JsonNumber(n.adev_v[i])},
                            {"adev_lo_v", JsonNumber(n.adev_lo_v[i])},
                            {"adev_hi_v", JsonNumber(n.adev_hi_v[i])},
                            {"edf", JsonNumber(n.edf[i])}});
        nlohmann::json unit =
            GYROCAL_JSON_FIELDS(n, sensor_id, utime, still_s, n_segments, longest_segment_s,
                                arw_v_rthz, arw_stderr_v_rthz, bias_instability_v,
                                bias_instability_stderr_v, rrw_v_rts, rrw_stderr_v_rts, fit_note);
        unit["sensitivity_v_per_dps"] = model::JsonValue(ni.sensitivity_v_per_dps);
        unit["adev"] = adev;
        noise.push_back(unit);
    }
    j["noise"] = noise;
}

}  // namespace gyrocal::format
