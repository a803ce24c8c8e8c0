#pragma once
// A list as one line of text: the items with a separator between them.
#include <string>
#include <string_view>

namespace gyrocal::text {

// The items (strings, in the container's order) joined by `sep`, "" for none; a separator goes
// before an item only once something has been written (empty first items take none).
template <class Items>
std::string Join(const Items& items, std::string_view sep) {
    std::string out;
    for (const auto& x : items) {
        if (!out.empty()) out += sep;
        out += x;
    }
    return out;
}

}  // namespace gyrocal::text
