#pragma once
// gyrocal-compensator's node: GYRO_*, POWER_* and COEFFS_* in; RATE_<id> and STATUS out.
// Threads: one. Bus::Handle dispatches on the caller's thread, so a coefficient set received
// between two samples is complete before the next sample is computed (the atomic swap). All
// numbers are decided by SensorCompensator (compensate.hpp); handlers guard, call it, publish.
#include <cstdint>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "gyrocal/coeff_set_t.hpp"
#include "gyrocal/gyro_sample_t.hpp"
#include "gyrocal/power_state_t.hpp"
#include "gyrocal/rate_t.hpp"
#include "lcmtypes/bus/bus.hpp"
#include "lcmtypes/process/status.hpp"
#include "processors/compensator/compensate.hpp"

namespace gyrocal::compensator::node {

struct CompensatorNodeOptions {
    std::string lcm_url;  // "" = $GYROCAL_LCM_URL or the default
    compensator::CompensatorOptions core;
    std::vector<std::string> sensors;  // empty = every sensor
    static CompensatorNodeOptions Defaults() { return {}; }
};

class CompensatorNode {
public:
    // Throws BusError when LCM cannot be opened.
    explicit CompensatorNode(const CompensatorNodeOptions& options);
    void Run();  // until SIGINT/SIGTERM
    // One dispatch round (tests): at most one message handled, its rates published; whether one
    // was.
    bool HandleFor(int timeout_ms);
    const process::StatusReporter& status() const { return status_; }
    bus::Bus& bus() { return bus_; }  // tests publish into it over memq://

private:
    void OnCoeffs(const coeff_set_t& m, const std::string& channel);
    void OnGyro(const gyro_sample_t& m, const std::string& channel);
    void OnPower(const power_state_t& m, const std::string& channel);
    // The sensor of a per-sensor channel when wanted and equal to the message's; else counted.
    bool Accept(std::string_view prefix, const std::string& channel, const std::string& msg_sensor,
                std::string* id);
    compensator::SensorCompensator& Comp(const std::string& id);
    void Rejected(const std::string& key, const std::string& detail);
    void UpdateStatus();
    // Publishes the rates of the message just handled: one rate_t for a single sample, one
    // rate_batch_t for a gyro_batch_t (a batch in, a batch out: bus/batch.hpp).
    void FlushRates();

    CompensatorNodeOptions options_;
    bus::Bus bus_;
    process::StatusReporter status_;
    std::set<std::string> only_;
    std::map<std::string, compensator::SensorCompensator> comps_;
    std::map<std::string, std::vector<rate_t>> pending_rates_;  // channel -> rates not yet sent
    int64_t uncompensated_ = 0, compensated_ = 0, out_of_range_ = 0, sets_applied_ = 0,
            sets_rejected_ = 0;
};

}  // namespace gyrocal::compensator::node
