#pragma once
// JSON form of models and coefficient sets (exports, `gyrocal compensate` input, the database's
// text columns). Field names are those of model_t / coeff_set_t. JSON has no NaN/Inf: a
// non-finite number is written as null and null reads back as NaN. Reading validates like
// FromMsg and throws ModelError naming the JSON field.
#include <nlohmann/json.hpp>

#include "processors/model/convert.hpp"

namespace gyrocal::model {

// A number as JSON: null when it is not finite (JSON has no NaN or infinity; a missing figure
// reads as null everywhere this project writes JSON).
nlohmann::json JsonNumber(double v);

nlohmann::json ToJson(const Model& model);
Model ModelFromJson(const nlohmann::json& j);

nlohmann::json ToJson(const CoeffSet& set);
CoeffSet CoeffSetFromJson(const nlohmann::json& j);

}  // namespace gyrocal::model
