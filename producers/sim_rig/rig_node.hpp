#pragma once
// gyrocal-sim-rig's node: the simulated rig (gyrocal_sim) on LCM.
//
// Threads: one. LCM's receive thread only queues CHAMBER_CMD / TURNTABLE_CMD; this thread runs
// RunLoop, and between bus polls advances the simulation up to where the pacing says the
// simulated clock should be (sim = start + speed * wall elapsed), publishing every sample due in
// that batch. Publication is also capped at --max-msgs-per-s (wall clock): a sender faster than
// the subscribers on the same host can drain only makes them lose samples, so past the cap the
// simulation slows down instead. When behind, batches are capped (commands are still served)
// and the lag is reported in STATUS (extra "lag_s"). With --speed 0 there is no speed: the
// simulation runs as fast as every consumer on the bus keeps up (flow control, lcmtypes/flow),
// batch by batch (--batch-samples per gyro and encoder message). It stops on SIGINT/SIGTERM, at
// --duration-s of simulated time, or when the built-in profile is done.
#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "gyrocal/chamber_cmd_t.hpp"
#include "gyrocal/turntable_cmd_t.hpp"
#include "lcmtypes/bus/bus.hpp"
#include "lcmtypes/bus/sample_batcher.hpp"
#include "lcmtypes/flow/flow_source.hpp"
#include "lcmtypes/process/flow_options.hpp"
#include "lcmtypes/process/status.hpp"
#include "producers/sim/builtin_profile.hpp"
#include "producers/sim/rig.hpp"

namespace gyrocal::sim_rig {

struct SimRigOptions {
    std::string lcm_url;              // "" = $GYROCAL_LCM_URL or the default
    std::string mode = "commanded";   // "commanded" or "builtin"
    double speed = 1.0;               // [sim s / wall s]; 0 = as fast as the consumers keep up
    double duration_s = 0.0;          // [s] simulated; 0 = until stopped (or profile done)
    std::string truth_out;            // truth sidecar JSON; "" = none
    double tick_ms = 5.0;             // [ms] wall time between publication batches
    double max_msgs_per_s = 30000.0;  // [1/s] wall-clock publication cap; 0 = none
    process::SourceFlowOptions flow =
        process::SourceFlowOptions::Defaults();  // --speed 0; batching always
    sim::RigConfig rig = sim::RigConfig::Defaults();
    sim::ProfileConfig profile = sim::ProfileConfig::Defaults();
    static SimRigOptions Defaults() { return {}; }
};

class SimRigNode : private sim::RigSink {
public:
    // Throws sim::ConfigError for a bad configuration, BusError when LCM cannot be opened.
    explicit SimRigNode(const SimRigOptions& options);
    // Runs until stopped; returns the process exit code.
    int Run();
    // The node's bus: tests publish commands to it and subscribe to it over memq:// (Handle it
    // after Run() for the last messages).
    bus::Bus& bus() { return bus_; }

private:
    // Guard: a built-in profile drives the rig itself; a command on the bus (`what`, e.g.
    // "chamber_cmd") is counted as refused, not obeyed.
    bool IgnoredInBuiltinMode(const std::string& what, int64_t cmd_id);
    void OnChamberCmd(const chamber_cmd_t& cmd);
    void OnTurntableCmd(const turntable_cmd_t& cmd);
    bool Advance();             // pacing step; true when finished
    bool AdvanceByConsumers();  // --speed 0: as far as the consumers have room for
    void UpdateProgress(int64_t target);
    bool OverMessageBudget() const;
    void OnGyro(const sim::GyroReading& r, const sim::GyroTruth& truth) override;
    void OnEncoder(const sim::EncoderReading& r) override;
    void OnChamber(const sim::ChamberReading& r) override;
    // POWER_<id> of every unit: before its first sample, then every kPowerRepeatS of sim time.
    void PublishPower(int64_t utime);

    SimRigOptions options_;
    bus::Bus bus_;
    process::StatusReporter status_;
    sim::Rig rig_;
    std::optional<sim::BuiltinProfile> profile_;
    std::vector<std::string> gyro_channels_;
    bus::SampleBatcher batcher_;
    std::unique_ptr<flow::FlowSource> flow_;  // --speed 0
    int64_t power_seq_ = 0;
    int64_t next_power_utime_ = 0;  // [us] sim time of the next POWER_<id> repeat
    std::chrono::steady_clock::time_point wall_start_;
    int64_t end_utime_ = 0;  // 0 = none
    bool finished_ = false;
};

}  // namespace gyrocal::sim_rig
