#include "store/runreport/unit_data.hpp"

#include <algorithm>
#include <cmath>
#include <set>

#include "processors/model/convert.hpp"
#include "store/db/model_rows.hpp"

namespace gyrocal::runreport {

namespace {

bool IsAnalysisSource(const std::string& source) { return source.rfind("analysis:", 0) == 0; }

nlohmann::json Config(const db::RunInfo& run) {
    const auto j = nlohmann::json::parse(run.config_json, nullptr, false);
    return j.is_object() ? j : nlohmann::json::object();
}

}  // namespace

std::vector<UnitData> Units(const db::RunDetail& d) {
    std::set<std::string> ids(d.run.sensor_ids.begin(), d.run.sensor_ids.end());
    for (const auto& p : d.plateaus) ids.insert(p.sensor_id);
    for (const auto& s : d.sensitivity_points) ids.insert(s.sensor_id);
    for (const auto& c : d.coeff_sets) ids.insert(c.set.sensor_id);
    for (const auto& a : d.analyses) ids.insert(a.sensor_id);
    std::vector<UnitData> units;
    for (const std::string& id : ids) {
        UnitData u;
        u.sensor_id = id;
        for (const auto& p : d.plateaus)
            if (p.sensor_id == id) u.plateaus.push_back(p);
        for (const auto& s : d.sensitivity_points)
            if (s.sensor_id == id) u.turns.push_back(s);
        for (const auto& c : d.coeff_sets) {
            if (c.set.sensor_id != id) continue;
            if (IsAnalysisSource(c.set.source)) {
                u.other_sets.push_back(c);
            } else if (!u.calibration || c.coeff_row_id > u.calibration->coeff_row_id) {
                if (u.calibration) u.other_sets.push_back(*u.calibration);
                u.calibration = c;
            } else {
                u.other_sets.push_back(c);
            }
        }
        for (const auto& a : d.analyses)
            if (a.sensor_id == id) u.analyses.push_back(a);
        if (u.calibration && u.calibration->set.source != model::kFitterSource)
            for (const auto& c : u.other_sets)
                if (c.set.source == model::kFitterSource &&
                    (!u.plateau_set || c.coeff_row_id > u.plateau_set->coeff_row_id))
                    u.plateau_set = c;
        if (u.calibration)
            for (const auto& a : u.analyses)
                if (a.coeff_row_id && *a.coeff_row_id == u.calibration->coeff_row_id)
                    u.final_analysis = a;
        units.push_back(std::move(u));
    }
    return units;
}

double PlateauSlowNoiseDps(const db::RunInfo& run) {
    const nlohmann::json c = Config(run);
    const auto it = c.find("plateau_slow_noise_dps");
    if (it == c.end() || !it->is_number()) return 0.0;
    const double v = it->get<double>();
    return std::isfinite(v) && v > 0 ? v : 0.0;
}

namespace {

// What measurement would test the candidates an analysis could not test ("to_test" of its JSON
// result); empty when the result does not say (or is not JSON).
std::vector<std::string> ToTest(const std::string& result_json) {
    std::vector<std::string> out;
    const nlohmann::json j = nlohmann::json::parse(result_json, nullptr, false);
    if (!j.is_object()) return out;
    const auto it = j.find("to_test");
    if (it == j.end() || !it->is_array()) return out;
    for (const nlohmann::json& t : *it)
        if (t.is_string()) out.push_back(t.get<std::string>());
    return out;
}

}  // namespace

acceptance::UnitEvidence Evidence(const UnitData& u, double slow_noise_dps) {
    acceptance::UnitEvidence e;
    e.sensor_id = u.sensor_id;
    e.plateau_slow_noise_dps = slow_noise_dps;
    if (u.calibration) {
        const db::CoeffSetRow& set = u.calibration->set;
        e.has_calibration = true;
        e.offset = db::ToModel(set.offset);
        e.sensitivity = db::ToModel(set.sensitivity);
        e.n_turns = static_cast<int>(set.rotation_ids.size());
        // What is about the plateaus is judged on the plateau set (header).
        const db::CoeffSetRow& plateau = u.plateau_set ? u.plateau_set->set : set;
        e.plateau_offset = db::ToModel(plateau.offset);
        e.plateau_sensitivity = db::ToModel(plateau.sensitivity);
        e.n_plateaus = static_cast<int>(plateau.plateau_ids.size());
        for (int64_t id : plateau.plateau_ids) {
            // A re-published plateau id keeps its newest row (the fitter keeps the newest too).
            const db::PlateauRow* found = nullptr;
            for (const auto& p : u.plateaus)
                if (p.plateau_id == id) found = &p;
            if (found)
                e.plateaus.push_back({found->temp_mean_c, found->gyro_mean_v, found->gyro_sem_v});
        }
    }
    if (u.final_analysis) {
        e.final_heldout_rate_rms_dps = u.final_analysis->rate_rms_dps_after;
        e.final_heldout_drift_dph = u.final_analysis->drift_dph_after;
        if (!std::isfinite(e.final_heldout_rate_rms_dps) ||
            !std::isfinite(e.final_heldout_drift_dph))
            e.final_heldout_note = "the analysis behind the final set has no held-out figure (" +
                                   u.final_analysis->verdict + ")";
    } else {
        e.final_heldout_note =
            "no analysis made the final set (a plateau set without the closed "
            "loop): its held-out error is not known";
    }
    if (!u.analyses.empty()) {
        const db::AnalysisRow& a = u.analyses.back();
        e.analysis_verdict = a.verdict;
        e.analysis_outcome = a.outcome;
        e.analysis_to_test = ToTest(a.result_json);
        e.analysis_stored_set = a.coeff_row_id.has_value();
    }
    return e;
}

RunLimits StoredLimits(const db::RunInfo& run) {
    RunLimits out;
    const nlohmann::json c = Config(run);
    const auto it = c.find(kLimitsKey);
    if (it == c.end() || it->is_null()) return out;
    const auto file = c.find(kLimitsFileKey);
    out.origin =
        "stored with run " + run.run_id +
        (file != c.end() && file->is_string() ? " (from " + file->get<std::string>() + ")" : "");
    try {
        out.limits = acceptance::FromJson(*it, "limits stored with run " + run.run_id);
    } catch (const acceptance::LimitsError& e) {
        out.problem = e.what();
    }
    return out;
}

std::vector<acceptance::UnitVerdict> Accept(const db::RunDetail& d,
                                            const acceptance::Limits& limits) {
    const double slow = PlateauSlowNoiseDps(d.run);
    std::vector<acceptance::UnitVerdict> out;
    for (const UnitData& u : Units(d))
        out.push_back(acceptance::Evaluate(limits, Evidence(u, slow)));
    return out;
}

acceptance::Outcome RunOutcome(const std::vector<acceptance::UnitVerdict>& verdicts) {
    using acceptance::Outcome;
    const auto any = [&](Outcome o) {
        return std::any_of(verdicts.begin(), verdicts.end(),
                           [o](const auto& v) { return v.outcome == o; });
    };
    if (verdicts.empty()) return Outcome::kNotEvaluated;
    return any(Outcome::kFail)           ? Outcome::kFail
           : any(Outcome::kNotEvaluated) ? Outcome::kNotEvaluated
                                         : Outcome::kPass;
}

}  // namespace gyrocal::runreport

namespace gyrocal::runreport {

RunAcceptance AcceptRun(const db::RunDetail& d, const std::optional<acceptance::Limits>& given,
                        const std::string& given_origin) {
    RunAcceptance a;
    if (given) {
        a.limits.limits = given;
        a.limits.origin = given_origin;
    } else {
        a.limits = StoredLimits(d.run);
    }
    if (a.limits.limits) a.verdicts = Accept(d, *a.limits.limits);
    return a;
}

std::string AcceptanceText(const RunAcceptance& a) {
    if (!a.limits.limits) {
        std::string s =
            "Acceptance: no limits for this run (gyrocal calibrate --limits FILE, or gyrocal "
            "report --limits FILE)\n";
        if (!a.limits.problem.empty())
            s += "  stored limits cannot be read: " + a.limits.problem + "\n";
        return s;
    }
    std::string s = "Acceptance (limits " + a.limits.origin +
                    "): " + acceptance::ToString(RunOutcome(a.verdicts)) + "\n";
    for (const auto& v : a.verdicts) s += "  " + acceptance::Summary(v) + "\n";
    return s;
}

nlohmann::json AcceptanceJson(const RunAcceptance& a) {
    nlohmann::json j;
    j["limits"] = a.limits.limits ? acceptance::ToJson(*a.limits.limits) : nlohmann::json(nullptr);
    j["limits_origin"] = a.limits.origin;
    if (!a.limits.problem.empty()) j["limits_problem"] = a.limits.problem;
    if (!a.limits.limits) return j;
    j["outcome"] = acceptance::ToString(RunOutcome(a.verdicts));
    nlohmann::json units = nlohmann::json::array();
    for (const auto& v : a.verdicts) {
        nlohmann::json checks = nlohmann::json::array();
        for (const auto& c : v.checks)
            checks.push_back({{"limit", c.key},
                              {"kind", c.kind},
                              {"unit", c.unit},
                              {"limit_value", c.kind == "require" ? nlohmann::json(true)
                                                                  : nlohmann::json(c.limit)},
                              {"measured", std::isfinite(c.measured) ? nlohmann::json(c.measured)
                                                                     : nlohmann::json(nullptr)},
                              {"measured_text", c.measured_text},
                              {"outcome", acceptance::ToString(c.outcome)},
                              {"note", c.note}});
        units.push_back({{"sensor_id", v.sensor_id},
                         {"outcome", acceptance::ToString(v.outcome)},
                         {"checks", checks}});
    }
    j["units"] = units;
    return j;
}

}  // namespace gyrocal::runreport
