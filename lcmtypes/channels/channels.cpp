#include "lcmtypes/channels/channels.hpp"

#include <stdexcept>

namespace gyrocal::channels {

bool IsValidSensorId(std::string_view id) {
    if (id.empty() || id.size() > 32) return false;
    for (char c : id) {
        const bool ok = (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') ||
                        (c >= '0' && c <= '9') || c == '_' || c == '-';
        if (!ok) return false;
    }
    return true;
}

std::string ValidateSensorIds(const std::vector<std::string>& sensor_ids,
                              const std::string& option) {
    for (const std::string& id : sensor_ids)
        if (!IsValidSensorId(id))
            return option + ": '" + id +
                   "' is not a valid sensor id (1-32 letters, digits, '-', '_')";
    return "";
}

std::string PerSensor(std::string_view prefix, std::string_view id) {
    if (!IsValidSensorId(id)) {
        throw std::invalid_argument("sensor id '" + std::string(id) +
                                    "' is not valid: use 1-32 letters, digits, '-' or '_'");
    }
    return std::string(prefix) + std::string(id);
}

std::string AllSensors(std::string_view prefix) { return std::string(prefix) + "[A-Za-z0-9_-]+"; }

std::optional<std::string> SensorOf(std::string_view prefix, std::string_view channel) {
    if (channel.substr(0, prefix.size()) != prefix) return std::nullopt;
    std::string_view id = channel.substr(prefix.size());
    if (!IsValidSensorId(id)) return std::nullopt;
    return std::string(id);
}

}  // namespace gyrocal::channels
