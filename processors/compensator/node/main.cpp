// gyrocal-compensator: applies the newest COEFFS_<id> to every GYRO_<id> sample and publishes
// RATE_<id>; the node is compensator_node.hpp.
#include <CLI/CLI.hpp>

#include "lcmtypes/channels/channels.hpp"
#include "lcmtypes/process/process_main.hpp"
#include "processors/compensator/node/compensator_node.hpp"

int main(int argc, char** argv) {
    constexpr const char* kProcess = "gyrocal-compensator";
    gyrocal::compensator::node::CompensatorNodeOptions o =
        gyrocal::compensator::node::CompensatorNodeOptions::Defaults();
    std::string policy = gyrocal::model::ToString(o.core.range_policy);
    CLI::App app{
        "gyrocal-compensator: applies the newest COEFFS_<id> to every GYRO_<id> sample and "
        "publishes RATE_<id> (rate_dps, integrated angle_deg, range_flag). Model inputs (dT/dt, "
        "heating/cooling branch, time since power-on from POWER_<id>) are tracked per sample as "
        "the coefficient set's terms define them.",
        kProcess};
    app.add_option(
        "--lcm-url", o.lcm_url,
        "LCM URL (default: $GYROCAL_LCM_URL or " + std::string(gyrocal::bus::kDefaultLcmUrl) + ")");
    app.add_option("--out-of-range", policy,
                   "outside a model's valid temperature range: extrapolate (continue the fitted "
                   "polynomial; default) or clip (evaluate at the nearest bound). Either way "
                   "rate_t.range_flag marks the sample (1 clipped, 2 extrapolated)")
        ->capture_default_str();
    app.add_option("--sensor", o.sensors,
                   "compensate only these sensor ids (repeatable); default: all");
    app.footer(gyrocal::process::kNodeExitCodes);
    const auto validate = [&]() -> std::string {
        const auto p = gyrocal::model::ParseRangePolicy(policy);
        if (!p) return "--out-of-range '" + policy + "' is not valid: use clip or extrapolate";
        o.core.range_policy = *p;
        return gyrocal::channels::ValidateSensorIds(o.sensors, "--sensor");
    };
    if (auto exit_code = gyrocal::process::ParseCommandLine(app, argc, argv, kProcess, validate))
        return *exit_code;
    return gyrocal::process::RunUntilStopped(
        kProcess, [&] { gyrocal::compensator::node::CompensatorNode(o).Run(); });
}
