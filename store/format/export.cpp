// The exports: a coefficient set as JSON, all sets as CSV (one line per term), and the C header
// firmware includes (models with their terms, T0 and valid range, and an evaluator).
#include <cmath>
#include <set>
#include <sstream>

#include "lcmtypes/text/number.hpp"
#include "processors/model/c_source.hpp"
#include "processors/model/inputs.hpp"
#include "processors/model/json.hpp"
#include "processors/model/terms.hpp"
#include "store/db/model_rows.hpp"
#include "store/format/format.hpp"
#include "store/format/format_util.hpp"

namespace gyrocal::format {
namespace {

std::string CsvField(const std::string& s) {
    if (s.find_first_of(",\"\n\r") == std::string::npos) return s;
    std::string out = "\"";
    for (char c : s) out += (c == '"') ? std::string("\"\"") : std::string(1, c);
    return out + "\"";
}

std::string CsvNum(double v) {
    if (!std::isfinite(v)) return "";
    return text::Sig(v, 17);
}

// Text safe inside a C block comment and on one line.
std::string CComment(const std::string& s) {
    std::string out = Printable(s);
    for (size_t at = out.find("*/"); at != std::string::npos; at = out.find("*/", at)) {
        out.replace(at, 2, "* /");
    }
    return out;
}

// Text safe inside a C string literal.
std::string CString(const std::string& s) {
    std::string out;
    for (unsigned char c : s) {
        out += (c < 0x20 || c >= 0x7f || c == '"' || c == '\\' || c == '?') ? '_'
                                                                            : static_cast<char>(c);
    }
    return out;
}

std::string CIdent(const std::string& s) {
    std::string out;
    for (unsigned char c : s) out += std::isalnum(c) ? static_cast<char>(c) : '_';
    return out.empty() ? "_" : out;
}

std::string CDouble(double v) {
    if (std::isnan(v)) return "NAN";
    if (std::isinf(v)) return v > 0 ? "INFINITY" : "-INFINITY";
    std::string s = text::Sig(v, 17);
    if (s.find_first_of(".eEn") == std::string::npos) s += ".0";
    return s;
}

}  // namespace

using namespace detail;

nlohmann::json CoeffSetJson(const db::CoeffSetInfo& c) {
    // The model library's writer (model/json.hpp: what `gyrocal compensate --coeffs` reads back),
    // plus where the set is stored.
    nlohmann::json j = model::ToJson(db::ToCoeffSet(c.set));
    j["coeff_row_id"] = c.coeff_row_id;
    j["recv_utime"] = c.set.recv_utime;
    return j;
}

std::string CoeffsCsv(const std::vector<db::CoeffSetInfo>& sets) {
    std::ostringstream out;
    out << "sensor_id,run_id,coeff_set_id,source,role,quantity,term_index,term_name,coeff,"
           "coeff_stddev,t0_c,temp_min_c,temp_max_c,residual_rms,n_points,method\n";
    for (const auto& s : sets) {
        for (const auto& [role, m] :
             {std::pair<const char*, const db::ModelRow*>{"offset", &s.set.offset},
              {"sensitivity", &s.set.sensitivity}}) {
            for (size_t i = 0; i < m->term_names.size(); ++i) {
                const double c = i < m->coeffs.size() ? m->coeffs[i] : NAN;
                const double var = i < m->covariance.size() && i < m->covariance[i].size()
                                       ? m->covariance[i][i]
                                       : NAN;
                out << CsvField(s.set.sensor_id) << "," << CsvField(s.set.run_id) << ","
                    << s.set.coeff_set_id << "," << CsvField(s.set.source) << "," << role << ","
                    << CsvField(m->quantity) << "," << i << "," << CsvField(m->term_names[i]) << ","
                    << CsvNum(c) << "," << CsvNum(var >= 0 ? std::sqrt(var) : NAN) << ","
                    << CsvNum(m->t0_c) << "," << CsvNum(m->temp_min_c) << ","
                    << CsvNum(m->temp_max_c) << "," << CsvNum(m->residual_rms) << "," << m->n_points
                    << "," << CsvField(m->method) << "\n";
            }
        }
    }
    return out.str();
}

namespace {

// "{GYROCAL_TERM_WARMUP, 600.0}" for a stored term name (the kind and parameter the C++ registry
// resolves it to: model/terms.hpp); an unknown name becomes GYROCAL_TERM_UNKNOWN, which the C
// evaluator turns into NAN (never a wrong number).
std::string CTermInit(const std::string& name) {
    model::ResolvedTerm t;
    if (!model::ResolveTerm(name, &t, nullptr)) return "{GYROCAL_TERM_UNKNOWN, 0.0}";
    return "{" + std::to_string(t.c.kind) + " /* " + CComment(name) + " */, " + CDouble(t.c.param) +
           "}";
}

// The tracker configuration a stored set needs (model/inputs.hpp), or why it has none.
std::optional<gyrocal_tracker_config_t> TrackerConfig(const db::CoeffSetInfo& s, std::string* why) {
    try {
        const model::Model off = db::ToModel(s.set.offset), sens = db::ToModel(s.set.sensitivity);
        return model::TrackerConfigFor({&off, &sens});
    } catch (const std::exception& e) {
        *why = e.what();
        return std::nullopt;
    }
}

void CModel(std::ostream& out, const std::string& id, const char* role, const db::ModelRow& m) {
    const size_t n = m.term_names.size();
    out << "/* " << role << ": " << CComment(m.quantity) << ", method " << CComment(m.method)
        << ", " << m.n_points << " points, residual rms " << text::SigOrDash(m.residual_rms, 4)
        << ", T0 " << text::SigOrDash(m.t0_c) << " C, valid " << text::SigOrDash(m.temp_min_c)
        << ".." << text::SigOrDash(m.temp_max_c) << " C */\n";
    if (n == 0) {
        out << "/* (no terms: this model was not fitted) */\n";
        out << "static const gyrocal_model_t " << id << " = {0, 0, 0, 0, " << CDouble(m.t0_c)
            << ", " << CDouble(m.temp_min_c) << ", " << CDouble(m.temp_max_c) << "};\n";
        return;
    }
    out << "static const char *const " << id << "_term_names[" << n << "] = {";
    for (size_t i = 0; i < n; ++i)
        out << (i ? ", " : "") << "\"" << CString(m.term_names[i]) << "\"";
    out << "};\n";
    out << "static const gyrocal_term_t " << id << "_terms[" << n << "] = {";
    for (size_t i = 0; i < n; ++i) out << (i ? ", " : "") << CTermInit(m.term_names[i]);
    out << "};\n";
    out << "static const double " << id << "_coeffs[" << n << "] = {";
    for (size_t i = 0; i < n; ++i)
        out << (i ? ", " : "") << CDouble(i < m.coeffs.size() ? m.coeffs[i] : NAN);
    out << "};\n";
    out << "static const gyrocal_model_t " << id << " = {" << n << ", " << id << "_term_names, "
        << id << "_terms, " << id << "_coeffs, " << CDouble(m.t0_c) << ", " << CDouble(m.temp_min_c)
        << ", " << CDouble(m.temp_max_c) << "};\n";
}

}  // namespace

std::string CoeffsCHeader(const std::vector<db::CoeffSetInfo>& sets, const std::string& origin) {
    std::ostringstream out;
    out << "/* gyrocal temperature compensation coefficients. Generated by `gyrocal export`; do not"
           " edit.\n"
        << " * Exported from: " << CComment(origin) << "\n"
        << " *\n"
        << " * Per sensor S: gyrocal_S_offset, gyrocal_S_sensitivity (models), gyrocal_S_tracker\n"
        << " * (the configuration of the input trackers the models need) and gyrocal_S_init().\n"
        << " * Use: gyrocal_compensator_t c; gyrocal_S_init(&c, GYROCAL_CLIP);\n"
        << " *      at boot, optionally: gyrocal_tracker_power_on(&c.tracker, boot_utime);\n"
        << " *      per raw sample, in time order: gyrocal_rate_t r;\n"
        << " *        if (gyrocal_compensate(&c, utime, gyro_v, temp_c, supply_v, &r)) use "
           "r.rate_dps;\n"
        << " * The code below is gyrocal's own model path (gyrocal_model.h), the same the live\n"
        << " * compensator and `gyrocal compensate` run: the same raw samples from the same start\n"
        << " * give the same rate. GYROCAL_CLIP holds temp_c at the valid range (the firmware\n"
        << " * default); GYROCAL_EXTRAPOLATE is what gyrocal's live compensator does (flagged).\n"
        << " */\n"
        << "#ifndef GYROCAL_COEFFS_H\n#define GYROCAL_COEFFS_H\n\n"
        << model::CModelSource() << "\n";
    std::set<std::string> used;
    for (const auto& s : sets) {
        std::string base = "gyrocal_" + CIdent(s.set.sensor_id);
        std::string name = base;
        for (int k = 2; used.count(name); ++k) name = base + "_" + std::to_string(k);
        used.insert(name);
        out << "\n/* Sensor " << CComment(s.set.sensor_id) << ": run " << CComment(s.set.run_id)
            << ", coefficient set " << s.set.coeff_set_id << " (source " << CComment(s.set.source)
            << "), recorded " << db::UtcText(s.set.recv_utime) << " UTC */\n";
        out << "#define GYROCAL_" << name.substr(8) << "_COEFF_SET_ID " << s.set.coeff_set_id
            << "LL\n";
        CModel(out, name + "_offset", "offset", s.set.offset);
        CModel(out, name + "_sensitivity", "sensitivity", s.set.sensitivity);
        std::string why;
        const auto config = TrackerConfig(s, &why);
        if (!config) {
            out << "/* no tracker configuration: " << CComment(why) << " */\n";
            continue;
        }
        out << "static const gyrocal_tracker_config_t " << name << "_tracker = {"
            << CDouble(config->rate_tau_s) << " /* dT/dt tau [s] */, "
            << CDouble(config->branch_width_c) << " /* branch width [degC] */};\n";
        out << "static inline void " << name << "_init(gyrocal_compensator_t *c, int policy) {\n"
            << "    gyrocal_compensator_init(c, &" << name << "_offset, &" << name
            << "_sensitivity, policy, " << name << "_tracker);\n}\n";
    }
    out << "\n#endif /* GYROCAL_COEFFS_H */\n";
    return out.str();
}

}  // namespace gyrocal::format
