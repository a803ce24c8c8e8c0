#pragma once
// JSON form of models and coefficient sets (exports, `gyrocal compensate` input, the database's
// text columns). Field names are those of model_t / coeff_set_t. JSON has no NaN/Inf: a
// non-finite number is written as null and null reads back as NaN. Reading validates like
// FromMsg and throws ModelError naming the JSON field.
#include <nlohmann/json.hpp>
#include <optional>

#include "processors/model/convert.hpp"

namespace gyrocal::model {

// A number as JSON: null when it is not finite (JSON has no NaN or infinity; a missing figure
// reads as null everywhere this project writes JSON).
nlohmann::json JsonNumber(double v);

// A field's value as this project writes it: a number by JsonNumber, an absent optional as null,
// anything else as nlohmann writes it.
inline nlohmann::json JsonValue(double v) { return JsonNumber(v); }
template <class T>
nlohmann::json JsonValue(const T& v) {
    return v;
}
template <class T>
nlohmann::json JsonValue(const std::optional<T>& v) {
    return v ? JsonValue(*v) : nlohmann::json(nullptr);
}

nlohmann::json ToJson(const Model& model);
Model ModelFromJson(const nlohmann::json& j);

nlohmann::json ToJson(const CoeffSet& set);
CoeffSet CoeffSetFromJson(const nlohmann::json& j);

}  // namespace gyrocal::model

// GYROCAL_JSON_FIELDS(o, a, b, c): the JSON object {"a": JsonValue(o.a), "b": ..., "c": ...}, each
// key its field's name, written once. For a JSON view that shows some of a struct's fields (a
// whole struct under its field names is NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE); it walks the list
// with nlohmann's own macros, those of NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE (up to 64 fields).
#define GYROCAL_JSON_FIELD(field) \
    gyrocal_json_fields_j[#field] = ::gyrocal::model::JsonValue(gyrocal_json_fields_o.field);
#define GYROCAL_JSON_FIELDS(from, ...)                                             \
    ([](const auto& gyrocal_json_fields_o) {                                       \
        nlohmann::json gyrocal_json_fields_j = nlohmann::json::object();           \
        NLOHMANN_JSON_EXPAND(NLOHMANN_JSON_PASTE(GYROCAL_JSON_FIELD, __VA_ARGS__)) \
        return gyrocal_json_fields_j;                                              \
    }(from))
