#pragma once
// An option renamed to carry its unit or the project's one name for a concept: --help lists the
// new name only, and the old one keeps working, hidden, so that scripts written for it go on.
#include <CLI/CLI.hpp>
#include <string>

namespace gyrocal::process {

// Adds `old_name` as a hidden option that parses a `T` into `value`, the variable `current`
// sets. Giving both names is a bad option (a CLI11 ValidationError naming both, exit 2), as
// giving one name twice is. Returns the hidden option (its count() says whether it was given).
template <class T, class Value>
CLI::Option* AddOldOptionName(CLI::App& app, const CLI::Option* current,
                              const std::string& old_name, Value& value) {
    const std::string name = current->get_name();
    return app
        .add_option_function<T>(old_name,
                                [&value, current, name, old_name](const T& parsed) {
                                    if (current->count() > 0) {
                                        throw CLI::ValidationError(old_name +
                                                                   " is the old name of " + name +
                                                                   ": give one of them");
                                    }
                                    value = parsed;
                                })
        ->group("");
}

}  // namespace gyrocal::process
