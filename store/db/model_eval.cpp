#include "model_eval.hpp"

#include <cmath>

namespace gyrocal::store {

std::optional<int> PolynomialPower(const std::string& term_name) {
    if (term_name == "1") return 0;
    if (term_name == "dT") return 1;
    if (term_name == "dT^2") return 2;
    if (term_name == "dT^3") return 3;
    return std::nullopt;
}

std::optional<double> EvalPolynomialModel(const std::vector<std::string>& term_names,
                                          const std::vector<double>& coeffs, double t0_c,
                                          double temp_c) {
    if (term_names.size() != coeffs.size()) return std::nullopt;
    const double dT = temp_c - t0_c;
    double y = 0.0;
    for (size_t i = 0; i < term_names.size(); ++i) {
        const std::optional<int> k = PolynomialPower(term_names[i]);
        if (!k) return std::nullopt;
        y += coeffs[i] * std::pow(dT, *k);
    }
    return y;
}

}  // namespace gyrocal::store
