#include "processors/model/json.hpp"

#include <cmath>

namespace gyrocal::model {

nlohmann::json JsonNumber(double v) {
    return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
}

namespace {

const nlohmann::json& Field(const nlohmann::json& j, const char* name, const std::string& where) {
    if (!j.is_object()) throw ModelError(where + ": must be a JSON object");
    auto it = j.find(name);
    if (it == j.end()) throw ModelError(where + "." + name + ": missing");
    return *it;
}

double GetNum(const nlohmann::json& j, const char* name, const std::string& where) {
    const nlohmann::json& v = Field(j, name, where);
    if (v.is_null()) return kUnknown;
    if (!v.is_number()) throw ModelError(where + "." + name + ": must be a number or null");
    return v.get<double>();
}

std::string GetStr(const nlohmann::json& j, const char* name, const std::string& where) {
    const nlohmann::json& v = Field(j, name, where);
    if (!v.is_string()) throw ModelError(where + "." + name + ": must be a string");
    return v.get<std::string>();
}

int64_t GetInt(const nlohmann::json& j, const char* name, const std::string& where) {
    const nlohmann::json& v = Field(j, name, where);
    if (!v.is_number_integer()) throw ModelError(where + "." + name + ": must be an integer");
    return v.get<int64_t>();
}

std::vector<int64_t> GetIds(const nlohmann::json& j, const char* name, const std::string& where) {
    const nlohmann::json& v = Field(j, name, where);
    if (!v.is_array()) throw ModelError(where + "." + name + ": must be an array of integers");
    std::vector<int64_t> ids;
    for (const auto& e : v) {
        if (!e.is_number_integer())
            throw ModelError(where + "." + name + ": must be an array of integers");
        ids.push_back(e.get<int64_t>());
    }
    return ids;
}

Model ModelFromJsonAt(const nlohmann::json& j, const std::string& where) {
    Model m;
    m.quantity = GetStr(j, "quantity", where);
    const nlohmann::json& names = Field(j, "term_names", where);
    const nlohmann::json& coeffs = Field(j, "coeffs", where);
    const nlohmann::json& cov = Field(j, "covariance", where);
    if (!names.is_array() || !coeffs.is_array() || !cov.is_array())
        throw ModelError(where + ": term_names, coeffs and covariance must be arrays");
    const auto n = static_cast<Eigen::Index>(names.size());
    if (static_cast<Eigen::Index>(coeffs.size()) != n || static_cast<Eigen::Index>(cov.size()) != n)
        throw ModelError(where + ": term_names (" + std::to_string(n) + "), coeffs (" +
                         std::to_string(coeffs.size()) + ") and covariance rows (" +
                         std::to_string(cov.size()) + ") must have the same length");
    m.coeffs.resize(n);
    m.covariance.resize(n, n);
    for (Eigen::Index i = 0; i < n; ++i) {
        const auto& name = names[static_cast<size_t>(i)];
        if (!name.is_string())
            throw ModelError(where + ".term_names[" + std::to_string(i) + "]: must be a string");
        m.term_names.push_back(name.get<std::string>());
        const auto& c = coeffs[static_cast<size_t>(i)];
        if (!c.is_null() && !c.is_number())
            throw ModelError(where + ".coeffs[" + std::to_string(i) + "]: must be a number");
        m.coeffs[i] = c.is_null() ? kUnknown : c.get<double>();
        const auto& row = cov[static_cast<size_t>(i)];
        if (!row.is_array() || static_cast<Eigen::Index>(row.size()) != n)
            throw ModelError(where + ".covariance[" + std::to_string(i) +
                             "]: must be an array of " + std::to_string(n) + " numbers");
        for (Eigen::Index k = 0; k < n; ++k) {
            const auto& e = row[static_cast<size_t>(k)];
            if (!e.is_null() && !e.is_number())
                throw ModelError(where + ".covariance[" + std::to_string(i) + "][" +
                                 std::to_string(k) + "]: must be a number or null");
            m.covariance(i, k) = e.is_null() ? kUnknown : e.get<double>();
        }
    }
    m.t0_c = GetNum(j, "t0_c", where);
    m.temp_min_c = GetNum(j, "temp_min_c", where);
    m.temp_max_c = GetNum(j, "temp_max_c", where);
    m.residual_rms = GetNum(j, "residual_rms", where);
    m.n_points = static_cast<int32_t>(GetInt(j, "n_points", where));
    m.condition_number = GetNum(j, "condition_number", where);
    m.method = GetStr(j, "method", where);
    const std::string problem = Validate(m);
    if (!problem.empty()) throw ModelError(where + ": " + problem);
    return m;
}

}  // namespace

nlohmann::json ToJson(const Model& m) {
    nlohmann::json j;
    j["quantity"] = m.quantity;
    j["term_names"] = m.term_names;
    nlohmann::json coeffs = nlohmann::json::array();
    nlohmann::json cov = nlohmann::json::array();
    for (Eigen::Index i = 0; i < m.coeffs.size(); ++i) coeffs.push_back(JsonNumber(m.coeffs[i]));
    // Row by row as stored, so a model whose sizes disagree (a damaged database row) is written
    // as it is and refused when read back, never read out of bounds.
    for (Eigen::Index i = 0; i < m.covariance.rows(); ++i) {
        nlohmann::json row = nlohmann::json::array();
        for (Eigen::Index k = 0; k < m.covariance.cols(); ++k)
            row.push_back(JsonNumber(m.covariance(i, k)));
        cov.push_back(row);
    }
    j["coeffs"] = coeffs;
    j["covariance"] = cov;
    j["t0_c"] = JsonNumber(m.t0_c);
    j["temp_min_c"] = JsonNumber(m.temp_min_c);
    j["temp_max_c"] = JsonNumber(m.temp_max_c);
    j["residual_rms"] = JsonNumber(m.residual_rms);
    j["n_points"] = m.n_points;
    j["condition_number"] = JsonNumber(m.condition_number);
    j["method"] = m.method;
    return j;
}

Model ModelFromJson(const nlohmann::json& j) { return ModelFromJsonAt(j, "model"); }

nlohmann::json ToJson(const CoeffSet& s) {
    nlohmann::json j;
    j["utime"] = s.utime;
    j["sensor_id"] = s.sensor_id;
    j["run_id"] = s.run_id;
    j["coeff_set_id"] = s.coeff_set_id;
    j["source"] = s.source;
    j["offset"] = ToJson(s.offset);
    j["sensitivity"] = ToJson(s.sensitivity);
    j["plateau_ids"] = s.plateau_ids;
    j["rotation_ids"] = s.rotation_ids;
    return j;
}

CoeffSet CoeffSetFromJson(const nlohmann::json& j) {
    const std::string where = "coeff_set";
    CoeffSet s;
    s.utime = GetInt(j, "utime", where);
    s.sensor_id = GetStr(j, "sensor_id", where);
    s.run_id = GetStr(j, "run_id", where);
    s.coeff_set_id = GetInt(j, "coeff_set_id", where);
    s.source = GetStr(j, "source", where);
    s.offset = ModelFromJsonAt(Field(j, "offset", where), where + ".offset");
    s.sensitivity = ModelFromJsonAt(Field(j, "sensitivity", where), where + ".sensitivity");
    if (s.offset.quantity != kOffsetQuantity)
        throw ModelError(where + ".offset.quantity: must be '" + std::string(kOffsetQuantity) +
                         "'");
    if (s.sensitivity.quantity != kSensitivityQuantity)
        throw ModelError(where + ".sensitivity.quantity: must be '" +
                         std::string(kSensitivityQuantity) + "'");
    s.plateau_ids = GetIds(j, "plateau_ids", where);
    s.rotation_ids = GetIds(j, "rotation_ids", where);
    return s;
}

}  // namespace gyrocal::model
