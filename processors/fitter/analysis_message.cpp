#include "processors/fitter/analysis_message.hpp"

#include "processors/analysis/report.hpp"
#include "processors/model/json.hpp"

namespace gyrocal::fitter {

namespace {

nlohmann::json ResidualJson(const plot::Table& t) {
    nlohmann::json rows = nlohmann::json::array();
    for (const auto& row : t.rows) {
        nlohmann::json r = nlohmann::json::array();
        for (double v : row) r.push_back(model::JsonNumber(v));
        rows.push_back(std::move(r));
    }
    return {{"columns", t.columns}, {"rows", rows}};
}

}  // namespace

std::optional<analysis_t> AnalysisMessage(const RampFitResult& res, const std::string& run_id,
                                          const std::string& source) {
    if (!res.analysis) return std::nullopt;
    const analysis::SensorResult& r = *res.analysis;
    analysis_t m;
    m.utime = res.report.utime;
    m.sensor_id = res.sensor_id;
    m.run_id = run_id;
    m.coeff_set_id = res.set ? res.set->coeff_set_id : -1;
    m.source = source;
    m.is_final = res.report.is_final;
    m.outcome = analysis::ToString(r.outcome);
    m.headline = r.headline;
    analysis::CopyBeforeAfter(r, m);
    m.floor_drift_dph = r.floor_drift_dph;
    nlohmann::json j = analysis::ToJson(r);
    m.candidates_json = j["candidates"].dump();
    m.added_json = j["added"].dump();
    if (res.residual) j["residual_bins"] = ResidualJson(*res.residual);
    m.result_json = j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
    return m;
}

}  // namespace gyrocal::fitter
