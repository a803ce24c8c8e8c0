#pragma once
// The configuration shared by the measured-data sources: the module preset, the temperature
// transfer function (the preset gives its defaults; explicit values win) and the encoder's
// counts per revolution. Validation returns one line naming the option and its valid range.
#include <cstdint>
#include <optional>
#include <string>

#include "producers/csv/row_messages.hpp"
#include "producers/sensor/temp_transfer.hpp"

namespace gyrocal::csv {

struct ConversionOptions {
    std::string preset = "610";
    std::optional<double> temp_v_at_25c;  // [V] overrides the preset
    std::optional<double> temp_v_per_c;   // [V/degC] overrides the preset
    int64_t encoder_counts_per_rev = kDefaultEncoderCountsPerRev;
    int64_t start_utime = kDefaultStartUtime;  // [us] utime of time_s = 0
    static ConversionOptions Defaults() { return {}; }

    // The resolved transfer function, or the error text (naming the option) in `error`.
    std::optional<sensor::TempTransfer> Transfer(std::string* error) const;
    // "" when every field is valid.
    std::string Validate() const;
};

}  // namespace gyrocal::csv
