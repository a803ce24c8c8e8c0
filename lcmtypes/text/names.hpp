#pragma once
// Enum values and their names in one table: the name a value prints as and the value a name
// parses to come from the same row, so printing and parsing cannot drift apart. A table is a
// constexpr std::array of {value, name} rows, declared once beside its enum:
//   constexpr text::NameTable<Method, 3> kMethodNames{{{Method::kAuto, "auto"}, ...}};
// What a switch gave and a table does not: the compiler's warning for an enumerator left out. A
// value missing from its table prints as `missing` ("?"), as the switches' fall-through did.
#include <array>
#include <cstddef>
#include <optional>
#include <string_view>
#include <utility>

namespace gyrocal::text {

template <class E, std::size_t N>
using NameTable = std::array<std::pair<E, const char*>, N>;

// The name of `value` in `table`, or `missing` when the table has no row for it.
template <class E, std::size_t N>
constexpr const char* NameOf(const NameTable<E, N>& table, E value, const char* missing = "?") {
    for (const auto& [v, name] : table)
        if (v == value) return name;
    return missing;
}

// The value named `name` in `table` (exact, case-sensitive), or nullopt.
template <class E, std::size_t N>
constexpr std::optional<E> ValueOf(const NameTable<E, N>& table, std::string_view name) {
    for (const auto& [v, n] : table)
        if (name == n) return v;
    return std::nullopt;
}

}  // namespace gyrocal::text
