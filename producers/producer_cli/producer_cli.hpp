#pragma once
// Command-line pieces the measured-data producers share (gyrocal-csv-source, gyrocal-line-source,
// gyrocal-csv-record; gyrocal-log-source the opening and --lcm-url), so their common options keep
// the same names, help texts and messages.
#include <CLI/CLI.hpp>
#include <string>
#include <utility>
#include <vector>

#include "producers/csv/conversion_options.hpp"

namespace gyrocal::producer_cli {

// --lcm-url: the LCM provider ("" = $GYROCAL_LCM_URL, else the default).
void AddLcmUrlOption(CLI::App& app, std::string& lcm_url);

// The opening every producer's command line shares: the --help footer, then the option that names
// what it reads or writes (`name`, e.g. "file,--file"; required when `required`), then --lcm-url.
// Returns that first option.
CLI::Option* AddOpeningOptions(CLI::App& app, const std::string& footer, const std::string& name,
                               std::string& target, const std::string& help, bool required,
                               std::string& lcm_url);

// --start-utime (`start_utime_help`: what time_s = 0 means differs per source), --preset,
// --temp-v-at-25c, --temp-v-per-c (also as its old name --temp-v-per-k, hidden),
// --encoder-counts-per-rev.
void AddConversionOptions(CLI::App& app, csv::ConversionOptions& conversion,
                          const std::string& start_utime_help);

// Sets `value` to the choice named `text`: "" when found, else the one-line error naming
// `option` and the valid names ("--time 'x' is unknown; valid: stream or wall").
template <class T>
std::string Choose(const std::string& option, const std::string& text,
                   const std::vector<std::pair<std::string, T>>& choices, T& value) {
    std::string valid;
    for (size_t i = 0; i < choices.size(); ++i) {
        if (choices[i].first == text) {
            value = choices[i].second;
            return "";
        }
        valid += (i == 0 ? "" : i + 1 == choices.size() ? " or " : ", ") + choices[i].first;
    }
    return option + " '" + text + "' is unknown; valid: " + valid;
}

}  // namespace gyrocal::producer_cli
