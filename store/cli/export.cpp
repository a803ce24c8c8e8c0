// The exports: a coefficient set as JSON, all sets as CSV (one line per term), and the C header
// firmware includes (models with their terms, T0 and valid range, and an evaluator).
#include <cmath>
#include <cstdio>
#include <set>
#include <sstream>

#include "format_util.hpp"
#include "model/terms.hpp"
#include "report.hpp"

namespace gyrocal::store::report {
namespace {

std::string CsvField(const std::string& s) {
    if (s.find_first_of(",\"\n\r") == std::string::npos) return s;
    std::string out = "\"";
    for (char c : s) out += (c == '"') ? std::string("\"\"") : std::string(1, c);
    return out + "\"";
}

std::string CsvNum(double v) {
    if (!std::isfinite(v)) return "";
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.17g", v);
    return buf;
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
        out += (c < 0x20 || c >= 0x7f || c == '"' || c == '\\' || c == '?') ? '_' : static_cast<char>(c);
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
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.17g", v);
    std::string s = buf;
    if (s.find_first_of(".eEn") == std::string::npos) s += ".0";
    return s;
}

}  // namespace

using namespace detail;

nlohmann::json CoeffSetJson(const CoeffSetInfo& c) {
    nlohmann::json j;
    j["coeff_row_id"] = c.coeff_row_id;
    j["sensor_id"] = c.set.sensor_id;
    j["run_id"] = c.set.run_id;
    j["coeff_set_id"] = c.set.coeff_set_id;
    j["source"] = c.set.source;
    j["utime"] = c.set.utime;
    j["recv_utime"] = c.set.recv_utime;
    j["offset"] = ModelJson(c.set.offset);
    j["sensitivity"] = ModelJson(c.set.sensitivity);
    j["plateau_ids"] = c.set.plateau_ids;
    j["rotation_ids"] = c.set.rotation_ids;
    return j;
}


std::string CoeffsCsv(const std::vector<CoeffSetInfo>& sets) {
    std::ostringstream out;
    out << "sensor_id,run_id,coeff_set_id,source,role,quantity,term_index,term_name,coeff,"
           "coeff_stddev,t0_c,temp_min_c,temp_max_c,residual_rms,n_points,method\n";
    for (const auto& s : sets) {
        for (const auto& [role, m] : {std::pair<const char*, const ModelRow*>{"offset", &s.set.offset},
                                      {"sensitivity", &s.set.sensitivity}}) {
            for (size_t i = 0; i < m->term_names.size(); ++i) {
                const double c = i < m->coeffs.size() ? m->coeffs[i] : NAN;
                const double var = i < m->covariance.size() && i < m->covariance[i].size()
                                       ? m->covariance[i][i] : NAN;
                out << CsvField(s.set.sensor_id) << "," << CsvField(s.set.run_id) << ","
                    << s.set.coeff_set_id << "," << CsvField(s.set.source) << "," << role << ","
                    << CsvField(m->quantity) << "," << i << "," << CsvField(m->term_names[i])
                    << "," << CsvNum(c) << "," << CsvNum(var >= 0 ? std::sqrt(var) : NAN) << ","
                    << CsvNum(m->t0_c) << "," << CsvNum(m->temp_min_c) << ","
                    << CsvNum(m->temp_max_c) << "," << CsvNum(m->residual_rms) << ","
                    << m->n_points << "," << CsvField(m->method) << "\n";
            }
        }
    }
    return out.str();
}

namespace {

// The C term kind of each registry term (model/terms.hpp), and how the C evaluator computes it.
// CHeaderKnowsTerm() lets a test walk model::AllTerms() so a new registry term cannot be missed.
struct CTerm {
    const char* name;  // registry name (the part before "(" for a parametric term)
    const char* kind;  // C enumerator
};
constexpr CTerm kCTerms[] = {
    {"1", "GYROCAL_TERM_ONE"},         {"dT", "GYROCAL_TERM_DT"},
    {"dT^2", "GYROCAL_TERM_DT2"},      {"dT^3", "GYROCAL_TERM_DT3"},
    {"dTdt", "GYROCAL_TERM_DTDT"},     {"heating", "GYROCAL_TERM_HEATING"},
    {"supply", "GYROCAL_TERM_SUPPLY"}, {"direction", "GYROCAL_TERM_DIRECTION"},
    {"warmup", "GYROCAL_TERM_WARMUP"},
};

// "{GYROCAL_TERM_WARMUP, 600.0}" for a stored term name; an unknown name becomes
// GYROCAL_TERM_UNKNOWN, which the C evaluator turns into NAN (never a wrong number).
std::string CTermInit(const std::string& name) {
    model::ResolvedTerm t;
    if (model::ResolveTerm(name, &t, nullptr)) {
        for (const CTerm& c : kCTerms) {
            if (t.def->name == c.name) {
                const double param = t.def->has_param ? t.param : 0.0;
                return std::string("{") + c.kind + ", " + CDouble(param) + "}";
            }
        }
    }
    return "{GYROCAL_TERM_UNKNOWN, 0.0}";
}

// The part of the header that does not depend on the coefficients: types and the evaluator,
// the C twin of model::Evaluator (same terms, same NaN rules, same range policies).
constexpr const char* kCPrelude = R"c(#ifndef GYROCAL_MODEL_T_DEFINED
#define GYROCAL_MODEL_T_DEFINED
/* What a model may depend on. Set what you measure; NAN = not known, and a term that needs an
 * unknown input makes the model NAN (never a silently wrong number). */
typedef struct {
    double temp_c;              /* [degC] sensor temperature */
    double dtemp_dt_c_per_s;    /* [degC/s] rate of change of temp_c */
    double supply_v;            /* [V] measured supply */
    double heating;             /* [1] +1 heating branch, -1 cooling branch */
    double direction;           /* [1] +1 / -1 rotation direction */
    double time_since_power_s;  /* [s] since the unit was powered */
} gyrocal_inputs_t;

/* Term kinds (gyrocal's term registry); dT = temp_c - t0_c. */
enum {
    GYROCAL_TERM_UNKNOWN = -1, /* a name this header does not know: evaluates to NAN */
    GYROCAL_TERM_ONE = 0,      /* "1"            1 */
    GYROCAL_TERM_DT,           /* "dT"           dT [degC] */
    GYROCAL_TERM_DT2,          /* "dT^2"         dT^2 [degC^2] */
    GYROCAL_TERM_DT3,          /* "dT^3"         dT^3 [degC^3] */
    GYROCAL_TERM_DTDT,         /* "dTdt"         dtemp_dt_c_per_s [degC/s] */
    GYROCAL_TERM_HEATING,      /* "heating"      sign(heating) */
    GYROCAL_TERM_SUPPLY,       /* "supply"       supply_v - GYROCAL_NOMINAL_SUPPLY_V [V] */
    GYROCAL_TERM_DIRECTION,    /* "direction"    sign(direction) */
    GYROCAL_TERM_WARMUP        /* "warmup(tau)"  exp(-time_since_power_s / tau) */
};
#define GYROCAL_NOMINAL_SUPPLY_V )c";

constexpr const char* kCEvaluator = R"c(
#define GYROCAL_CLIP 0        /* temp_c clipped to [temp_min_c, temp_max_c]: the default */
#define GYROCAL_EXTRAPOLATE 1 /* the polynomial used outside the range the fit saw */

typedef struct {
    int kind;      /* GYROCAL_TERM_* */
    double param;  /* parameter of a parametric term (warmup: tau [s]); 0 otherwise */
} gyrocal_term_t;

typedef struct {
    int num_terms;
    const char *const *term_names;  /* gyrocal's names, e.g. "1", "dT^2", "warmup(600)" */
    const gyrocal_term_t *terms;    /* how each is computed */
    const double *coeffs;           /* [unit of y / unit of term] */
    double t0_c;                    /* [degC] reference temperature of dT */
    double temp_min_c;              /* [degC] valid range: what the fit saw */
    double temp_max_c;              /* [degC] */
} gyrocal_model_t;

static inline double gyrocal_sign(double v) {
    if (!isfinite(v)) return NAN;
    return v > 0.0 ? 1.0 : (v < 0.0 ? -1.0 : 0.0);
}

static inline double gyrocal_term_value(const gyrocal_term_t *t, double dT,
                                        const gyrocal_inputs_t *in) {
    switch (t->kind) {
    case GYROCAL_TERM_ONE: return 1.0;
    case GYROCAL_TERM_DT: return dT;
    case GYROCAL_TERM_DT2: return dT * dT;
    case GYROCAL_TERM_DT3: return dT * dT * dT;
    case GYROCAL_TERM_DTDT: return in->dtemp_dt_c_per_s;
    case GYROCAL_TERM_HEATING: return gyrocal_sign(in->heating);
    case GYROCAL_TERM_SUPPLY: return in->supply_v - GYROCAL_NOMINAL_SUPPLY_V;
    case GYROCAL_TERM_DIRECTION: return gyrocal_sign(in->direction);
    case GYROCAL_TERM_WARMUP: return exp(-in->time_since_power_s / t->param);
    default: return NAN;
    }
}

/* y = sum_i coeffs[i] * term_i, polynomial terms from temp_c (clipped or not, per policy),
 * the others from the inputs. NAN when temp_c is not finite. */
static inline double gyrocal_eval_policy(const gyrocal_model_t *m, const gyrocal_inputs_t *in,
                                         int policy) {
    double t = in->temp_c, dT, y = 0.0;
    int i;
    if (!isfinite(t)) return NAN;
    if (policy == GYROCAL_CLIP) {
        if (t < m->temp_min_c) t = m->temp_min_c;
        if (t > m->temp_max_c) t = m->temp_max_c;
    }
    dT = t - m->t0_c;
    for (i = 0; i < m->num_terms; ++i) y += m->coeffs[i] * gyrocal_term_value(&m->terms[i], dT, in);
    return y;
}

/* The compensator's default: temp_c clipped to the valid range. */
static inline double gyrocal_eval(const gyrocal_model_t *m, const gyrocal_inputs_t *in) {
    return gyrocal_eval_policy(m, in, GYROCAL_CLIP);
}

/* [deg/s] compensated rate of a gyro reading gyro_v [V]. */
static inline double gyrocal_rate_dps(const gyrocal_model_t *offset,
                                      const gyrocal_model_t *sensitivity, double gyro_v,
                                      const gyrocal_inputs_t *in) {
    return (gyro_v - gyrocal_eval(offset, in)) / gyrocal_eval(sensitivity, in);
}
#endif
)c";

}  // namespace

bool CHeaderKnowsTerm(std::string_view registry_name) {
    for (const CTerm& c : kCTerms) {
        if (registry_name == c.name) return true;
    }
    return false;
}

std::string CoeffsCHeader(const std::vector<CoeffSetInfo>& sets, const std::string& origin) {
    std::ostringstream out;
    out << "/* gyrocal temperature compensation coefficients. Generated by `gyrocal export`; do not"
           " edit.\n"
        << " * Exported from: " << CComment(origin) << "\n"
        << " *\n"
        << " * Each model: y = sum_i coeffs[i] * term_i, dT = temp_c - t0_c [degC]; the\n"
        << " * polynomial terms (1, dT, dT^2, dT^3) come from temp_c, clipped to\n"
        << " * [temp_min_c, temp_max_c] by default (the fit saw no data outside), the others\n"
        << " * (dTdt, heating, supply, direction, warmup(tau)) from the gyrocal_inputs_t you fill.\n"
        << " *   offset_v                [V]\n"
        << " *   sensitivity_v_per_dps   [V/(deg/s)]\n"
        << " *   rate_dps = (gyro_v - offset_v) / sensitivity_v_per_dps  (gyrocal_rate_dps)\n"
        << " */\n"
        << "#ifndef GYROCAL_COEFFS_H\n#define GYROCAL_COEFFS_H\n\n#include <math.h>\n\n"
        << kCPrelude << CDouble(model::kNominalSupplyV) << " /* [V] */\n"
        << kCEvaluator;
    std::set<std::string> used;
    for (const auto& s : sets) {
        std::string base = "gyrocal_" + CIdent(s.set.sensor_id);
        std::string name = base;
        for (int k = 2; used.count(name); ++k) name = base + "_" + std::to_string(k);
        used.insert(name);
        out << "\n/* Sensor " << CComment(s.set.sensor_id) << ": run " << CComment(s.set.run_id)
            << ", coefficient set " << s.set.coeff_set_id << " (source "
            << CComment(s.set.source) << "), recorded " << UtcText(s.set.recv_utime)
            << " UTC */\n";
        out << "#define GYROCAL_" << name.substr(8)
            << "_COEFF_SET_ID " << s.set.coeff_set_id << "LL\n";
        for (const auto& [role, m] : {std::pair<const char*, const ModelRow*>{"offset", &s.set.offset},
                                      {"sensitivity", &s.set.sensitivity}}) {
            const std::string id = name + "_" + role;
            const size_t n = m->term_names.size();
            out << "/* " << role << ": " << CComment(m->quantity) << ", method "
                << CComment(m->method) << ", " << m->n_points << " points, residual rms "
                << Num(m->residual_rms, 4) << ", T0 " << Num(m->t0_c) << " C, valid "
                << Num(m->temp_min_c) << ".." << Num(m->temp_max_c) << " C */\n";
            if (n == 0) {
                out << "/* (no terms: this model was not fitted) */\n";
                out << "static const gyrocal_model_t " << id << " = {0, 0, 0, 0, "
                    << CDouble(m->t0_c) << ", " << CDouble(m->temp_min_c) << ", "
                    << CDouble(m->temp_max_c) << "};\n";
                continue;
            }
            out << "static const char *const " << id << "_term_names[" << n << "] = {";
            for (size_t i = 0; i < n; ++i) out << (i ? ", " : "") << "\"" << CString(m->term_names[i]) << "\"";
            out << "};\n";
            out << "static const gyrocal_term_t " << id << "_terms[" << n << "] = {";
            for (size_t i = 0; i < n; ++i) out << (i ? ", " : "") << CTermInit(m->term_names[i]);
            out << "};\n";
            out << "static const double " << id << "_coeffs[" << n << "] = {";
            for (size_t i = 0; i < n; ++i) {
                out << (i ? ", " : "") << CDouble(i < m->coeffs.size() ? m->coeffs[i] : NAN);
            }
            out << "};\n";
            out << "static const gyrocal_model_t " << id << " = {" << n << ", " << id
                << "_term_names, " << id << "_terms, " << id << "_coeffs, " << CDouble(m->t0_c)
                << ", " << CDouble(m->temp_min_c) << ", " << CDouble(m->temp_max_c) << "};\n";
        }
    }
    out << "\n#endif /* GYROCAL_COEFFS_H */\n";
    return out.str();
}

}  // namespace gyrocal::store::report
