#include "producers/sensor/temp_transfer.hpp"

#include <cmath>
#include <sstream>

namespace gyrocal::sensor {

std::optional<TempTransfer> PresetTransfer(const std::string& preset) {
    // Both datasheets give the same temperature output; the presets differ in rate sensitivity,
    // which replayed data already carries in its volts.
    if (preset == "610") return TempTransfer{2.5, 0.009};
    if (preset == "613") return TempTransfer{2.5, 0.009};
    return std::nullopt;
}

std::string ValidateTransfer(const TempTransfer& t) {
    std::ostringstream os;
    if (!std::isfinite(t.v_at_25c) || t.v_at_25c < -10.0 || t.v_at_25c > 10.0) {
        os << "--temp-v-at-25c " << t.v_at_25c << " is out of range; valid: -10 to 10 V";
    } else if (!std::isfinite(t.v_per_c) || t.v_per_c <= 0.0 || t.v_per_c > 1.0) {
        os << "--temp-v-per-c " << t.v_per_c << " is out of range; valid: > 0 and <= 1 V/degC";
    }
    return os.str();
}

}  // namespace gyrocal::sensor
