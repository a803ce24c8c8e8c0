#include "producers/sim/builtin_profile.hpp"

#include <cmath>
#include <sstream>

namespace gyrocal::sim {

std::vector<double> ParseProfile(const std::string& text, const ThermalConfig& thermal) {
    std::vector<double> out;
    std::stringstream ss(text);
    std::string item;
    std::ostringstream range;
    range << thermal.min_setpoint_c << " .. " << thermal.max_setpoint_c;
    const std::string valid =
        "valid: 1..64 comma-separated setpoints in degC within " + range.str() + ", e.g. -10,30,60";
    while (std::getline(ss, item, ',')) {
        double v = 0.0;
        try {
            size_t used = 0;
            v = std::stod(item, &used);
            while (used < item.size() && item[used] == ' ') ++used;
            if (used != item.size()) throw std::invalid_argument("trailing");
        } catch (const std::exception&) {
            throw ConfigError("--profile '" + text + "': '" + item + "' is not a number; " + valid);
        }
        if (!std::isfinite(v) || v < thermal.min_setpoint_c || v > thermal.max_setpoint_c) {
            throw ConfigError("--profile '" + text + "': setpoint '" + item + "' out of range; " +
                              valid);
        }
        out.push_back(v);
    }
    if (out.empty() || out.size() > 64) throw ConfigError("--profile '" + text + "': " + valid);
    return out;
}

BuiltinProfile::BuiltinProfile(ProfileConfig config) : config_(std::move(config)) {
    if (config_.setpoints_c.empty()) phase_ = Phase::kDone;
}

void BuiltinProfile::Enter(Phase phase, int64_t utime) {
    phase_ = phase;
    phase_start_utime_ = utime;
}

void BuiltinProfile::OrderSetpoint(Rig& rig, int64_t utime) {
    rig.ChamberCommand(index_ + 1, config_.setpoints_c[index_], 0.0);
    Enter(Phase::kRamping, utime);
}

void BuiltinProfile::OrderTurn(Rig& rig, double move_deg, Phase moving, int64_t utime) {
    rig.TurntableCommand(next_table_cmd_id_++, move_deg, 0.0, 0.0);
    Enter(moving, utime);
}

void BuiltinProfile::OnChamber(const ChamberReading& r, Rig& rig) {
    const double in_phase_s = (r.utime - phase_start_utime_) * 1e-6;
    switch (phase_) {
        case Phase::kStart:
            OrderSetpoint(rig, r.utime);
            break;
        case Phase::kRamping:
            // The reading was taken before this order took effect when both are at one instant.
            if (r.cmd_id == index_ + 1 && r.at_setpoint) Enter(Phase::kDwell, r.utime);
            break;
        case Phase::kDwell:
            if (in_phase_s >= config_.dwell_s)
                OrderTurn(rig, config_.move_deg, Phase::kMovePlus, r.utime);
            break;
        case Phase::kMovePlus:
            if (!rig.table_busy()) Enter(Phase::kRestPlus, r.utime);
            break;
        case Phase::kRestPlus:
            if (in_phase_s >= config_.rest_s)
                OrderTurn(rig, -config_.move_deg, Phase::kMoveMinus, r.utime);
            break;
        case Phase::kMoveMinus:
            if (!rig.table_busy()) Enter(Phase::kRestMinus, r.utime);
            break;
        case Phase::kRestMinus:
            if (in_phase_s >= config_.rest_s) {
                ++index_;
                if (index_ >= static_cast<int>(config_.setpoints_c.size()))
                    Enter(Phase::kDone, r.utime);
                else
                    OrderSetpoint(rig, r.utime);
            }
            break;
        case Phase::kDone:
            break;
    }
}

}  // namespace gyrocal::sim
