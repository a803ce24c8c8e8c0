#pragma once
// Evaluation of a stored model at a temperature, for `gyrocal history` and the exports.
//
// TEMPORARY, local: only the polynomial terms "1", "dT", "dT^2", "dT^3" (dT = temp_c - t0_c)
// are known here. The shared term evaluator (processors/model, library gyrocal_model) is to
// replace this one function; a model with any other term is reported as not evaluable rather
// than guessed.
#include <optional>
#include <string>
#include <vector>

namespace gyrocal::store {

// y(temp_c) = sum_i coeffs[i] * term_i(dT); nullopt when a term is not one of the polynomial
// terms above, or when the lengths differ.
std::optional<double> EvalPolynomialModel(const std::vector<std::string>& term_names,
                                          const std::vector<double>& coeffs, double t0_c,
                                          double temp_c);

// The power k of a term "1" (0), "dT" (1), "dT^k" (k = 2, 3); nullopt for other terms.
std::optional<int> PolynomialPower(const std::string& term_name);

}  // namespace gyrocal::store
