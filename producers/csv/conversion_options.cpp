#include "producers/csv/conversion_options.hpp"

namespace gyrocal::csv {

std::optional<sensor::TempTransfer> ConversionOptions::Transfer(std::string* error) const {
    std::optional<sensor::TempTransfer> t = sensor::PresetTransfer(preset);
    if (!t) {
        *error = "--preset '" + preset + "' is unknown; valid: " + sensor::kValidPresets;
        return std::nullopt;
    }
    if (temp_v_at_25c) t->v_at_25c = *temp_v_at_25c;
    if (temp_v_per_c) t->v_per_c = *temp_v_per_c;
    *error = sensor::ValidateTransfer(*t);
    if (!error->empty()) return std::nullopt;
    return t;
}

std::string ConversionOptions::Validate() const {
    std::string error;
    if (!Transfer(&error)) return error;
    if (encoder_counts_per_rev < 1 || encoder_counts_per_rev > 1'000'000'000) {
        return "--encoder-counts-per-rev " + std::to_string(encoder_counts_per_rev) +
               " is out of range; valid: 1 to 1000000000 counts per revolution";
    }
    // 0 allows time_s in Unix-epoch seconds; 4e18 leaves room for kMaxAbsTimeS of data time.
    if (start_utime < 0 || start_utime > 4'000'000'000'000'000'000) {
        return "--start-utime " + std::to_string(start_utime) +
               " is out of range; valid: 0 to 4e18 us";
    }
    return "";
}

}  // namespace gyrocal::csv
