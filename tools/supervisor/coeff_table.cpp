#include "tools/supervisor/coeff_table.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "lcmtypes/text/number.hpp"
#include "processors/model/convert.hpp"
#include "processors/model/inputs.hpp"
#include "processors/model/model.hpp"

namespace gyrocal::supervisor {
namespace {

void ModelBlock(std::ostringstream& os, const char* label, const model_t& m) {
    os << "  " << label << " [" << m.quantity << "]  method " << m.method << ", T0 "
       << text::Printf("%.2f", m.t0_c) << " C, range " << text::Printf("%.2f", m.temp_min_c) << ".."
       << text::Printf("%.2f", m.temp_max_c) << " C, " << m.n_points << " points, residual RMS "
       << text::Printf("%.3g", m.residual_rms) << ", cond "
       << text::Printf("%.3g", m.condition_number) << "\n";
    for (int i = 0; i < m.num_terms; ++i) {
        const double var = m.covariance.size() > static_cast<size_t>(i) &&
                                   m.covariance[i].size() > static_cast<size_t>(i)
                               ? m.covariance[i][i]
                               : NAN;
        os << text::Printf("      %-8s %+.6e  +- %.2e\n", m.term_names[i].c_str(), m.coeffs[i],
                           std::sqrt(var));
    }
}

// Evaluates a truth curve {"terms": [...], "coeffs": [...], "t0_c": x} at a die temperature.
double TruthAt(const nlohmann::json& curve, double die_c) {
    model::Model m;
    m.quantity = "truth";
    m.term_names = curve.at("terms").get<std::vector<std::string>>();
    const auto c = curve.at("coeffs").get<std::vector<double>>();
    m.coeffs = Eigen::Map<const Eigen::VectorXd>(c.data(), static_cast<Eigen::Index>(c.size()));
    m.covariance = Eigen::MatrixXd::Constant(m.coeffs.size(), m.coeffs.size(), NAN);
    m.t0_c = curve.at("t0_c").get<double>();
    m.temp_min_c = -1e9;
    m.temp_max_c = 1e9;
    model::ModelInputs in;
    in.temp_c = die_c;
    return model::Evaluator(m).Value(in, model::RangePolicy::kExtrapolate);
}

}  // namespace

std::string FormatCoeffTable(const std::map<std::string, coeff_set_t>& coeffs,
                             const std::map<std::string, std::string>& labels) {
    std::ostringstream os;
    os << "coefficient sets (1-sigma from the fit's covariance)\n";
    for (const auto& [id, c] : coeffs) {
        auto label = labels.find(id);
        os << id << ": set " << c.coeff_set_id << " from " << c.source << ", run " << c.run_id
           << ", " << c.num_plateaus << " plateaus, " << c.num_rotations << " rotations"
           << (label != labels.end() && !label->second.empty() ? "  ** " + label->second + " **"
                                                               : "")
           << "\n";
        ModelBlock(os, "offset     ", c.offset);
        ModelBlock(os, "sensitivity", c.sensitivity);
    }
    return os.str();
}

std::string FormatTruthComparison(const std::map<std::string, coeff_set_t>& coeffs,
                                  const nlohmann::json& truth) {
    if (truth.value("format", "") != "gyrocal-sim-truth/1")
        throw std::runtime_error("truth file: format is not gyrocal-sim-truth/1");
    std::ostringstream os;
    os << "fitted vs true (simulated rig truth; compared at equal die temperature, see "
          "coeff_table.hpp)\n";
    os << "sensor  die_C   offset_fit_V  offset_true_V  err_mV   err_dps  | sens_fit_mV/dps "
          "sens_true_mV/dps err_%\n";
    for (const auto& unit : truth.at("units")) {
        const std::string id = unit.at("sensor_id");
        auto it = coeffs.find(id);
        if (it == coeffs.end()) {
            os << id << ": no coefficient set\n";
            continue;
        }
        const double sensor_offset_c = unit.at("temp_sensor_offset_c").get<double>();
        model::Evaluator off(model::FromMsg(it->second.offset));
        model::Evaluator sens(model::FromMsg(it->second.sensitivity));
        const double lo = it->second.offset.temp_min_c - sensor_offset_c;
        const double hi = it->second.offset.temp_max_c - sensor_offset_c;
        double worst_dps = 0, worst_pct = 0;
        const int steps = 4;
        for (int k = 0; k <= steps; ++k) {
            const double die_c = lo + (hi - lo) * k / steps;
            // At rest in steady state: a set with dynamic terms (dT/dt, branch) compares too.
            const double t_c = die_c + sensor_offset_c;
            const double off_fit =
                off.Value(model::SteadyStateInputs(off.model(), t_c), model::RangePolicy::kClip);
            const double sens_fit =
                sens.Value(model::SteadyStateInputs(sens.model(), t_c), model::RangePolicy::kClip);
            const double off_true = TruthAt(unit.at("offset_v"), die_c);
            const double sens_true = TruthAt(unit.at("sensitivity_v_per_dps"), die_c);
            const double err_dps = (off_fit - off_true) / sens_true;
            const double err_pct = 100.0 * (sens_fit - sens_true) / sens_true;
            worst_dps = std::max(worst_dps, std::abs(err_dps));
            worst_pct = std::max(worst_pct, std::abs(err_pct));
            os << text::Printf(
                "%-6s %6.1f  %12.6f  %13.6f  %+7.3f  %+8.4f  | %15.4f %16.4f %+6.3f\n", id.c_str(),
                die_c, off_fit, off_true, 1e3 * (off_fit - off_true), err_dps, 1e3 * sens_fit,
                1e3 * sens_true, err_pct);
        }
        os << text::Printf("%-6s worst: offset %.4f deg/s, sensitivity %.3f %%\n", id.c_str(),
                           worst_dps, worst_pct);
    }
    return os.str();
}

}  // namespace gyrocal::supervisor
