// What `gyrocal calibrate` prints about the closed loop of a plateau run: per unit, the final
// set's analysis in one line (its outcome and headline), the error before (the declared model)
// and after (with the terms the data confirmed) on held-out data with the floor, and what it could
// not explain or test.
#include <nlohmann/json.hpp>

#include "lcmtypes/text/number.hpp"
#include "processors/model/convert.hpp"
#include "tools/supervisor/launcher.hpp"

namespace gyrocal::supervisor {

namespace {

std::string Terms(const model_t& m) {
    std::string s;
    for (const std::string& t : m.term_names) s += (s.empty() ? "" : ", ") + t;
    return "{" + s + "}";
}

// "0.0412 -> 0.0188" with 3 significant digits, "-" for a figure not computed.
std::string BeforeAfter(double before, double after) {
    auto f = [](double v) { return std::isfinite(v) ? text::Sig(v, 3) : std::string("-"); };
    return f(before) + " -> " + f(after);
}

}  // namespace

std::string Calibration::ClosedLoopLines() const {
    std::string out = "final sets (source " + std::string(model::kClosedLoopSource) +
                      ": fitted on every still sample with the terms the data confirm; the plateau "
                      "sets, source " +
                      model::kFitterSource +
                      ", are stored beside them). Held-out error, declared model -> final set:\n";
    for (const auto& [id, a] : loop_analyses_) {
        out += id + ": " + a.outcome + ": " + a.headline + "\n";
        out += "    held-out rate RMS " + BeforeAfter(a.rate_rms_dps_before, a.rate_rms_dps_after) +
               " deg/s (floor " + text::Sig(a.floor_rate_rms_dps, 3) + "), drift " +
               BeforeAfter(a.drift_dph_before, a.drift_dph_after) + " deg/h (floor " +
               text::Sig(a.floor_drift_dph, 3) + ")";
        const auto set = coeffs_.find(id);
        const auto rep = loop_reports_.find(id);
        if (a.coeff_set_id < 0)
            out += "\n    no final set (the plateau set stays in force): " +
                   (rep != loop_reports_.end() ? rep->second.reason : std::string("no report"));
        else if (set != coeffs_.end() && set->second.coeff_set_id == a.coeff_set_id &&
                 set->second.source == a.source)
            out += "; offset terms " + Terms(set->second.offset);
        out += "\n";
        if (a.outcome == "partly explained" || a.outcome == "unexplained residual")
            out +=
                "    not explained: what is left is above the floor bound (the headline says "
                "where and what it correlates with)\n";
        const nlohmann::json j = nlohmann::json::parse(a.result_json, nullptr, false);
        if (j.is_object() && j.contains("to_test") && j["to_test"].is_array() &&
            !j["to_test"].empty()) {
            std::string t;
            for (const auto& x : j["to_test"]) t += (t.empty() ? "" : "; ") + x.get<std::string>();
            out += "    could not test: " + t + "\n";
        }
    }
    for (const auto& [id, r] : loop_reports_)
        if (!loop_analyses_.count(id) && r.status != "complete")
            out += id + ": no closed loop: " + r.reason + "\n";
    return out;
}

}  // namespace gyrocal::supervisor
