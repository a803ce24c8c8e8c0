#pragma once
// Sensor ids must be usable as channel suffixes (see lcmtypes/bus/channels.hpp: letters, digits,
// '-' and '_', 1..32 chars). Checked here without linking the bus, which would pull in LCM.
#include <string>

namespace gyrocal::sim {

inline bool IsPlainSensorId(const std::string& id) {
    if (id.empty() || id.size() > 32) return false;
    for (char c : id) {
        const bool ok = (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') ||
                        (c >= '0' && c <= '9') || c == '_' || c == '-';
        if (!ok) return false;
    }
    return true;
}

}  // namespace gyrocal::sim
