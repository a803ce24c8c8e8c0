#pragma once
// gyrocal-replay's node: publishes a stored run back onto LCM (gyro, encoder and chamber samples
// and the run events) with its original timing, `speed` times faster, or as fast as every
// consumer keeps up (`max`: flow control, lcmtypes/flow; with no consumer answering, with no
// timing at all), so that processors can run again on historic data.
// Threads: one. Run() reads the next row (merged across tables by reception time), waits until
// its time (in short steps, so SIGINT/SIGTERM is honoured during long gaps) or until the
// consumers have room, publishes it. With `max` it ends once every consumer has answered the
// last mark.
#include <cstdint>
#include <memory>
#include <string>

#include "lcmtypes/bus/bus.hpp"
#include "lcmtypes/flow/flow_source.hpp"
#include "lcmtypes/process/flow_options.hpp"
#include "store/db/replay_reader.hpp"
#include "store/db/sqlite_db.hpp"

namespace gyrocal::replay {

inline constexpr const char* kReplayProcess = "gyrocal-replay";

struct ReplayOptions {
    std::string db_path = "gyrocal.db";
    std::string run_id;
    std::string lcm_url;  // "" = $GYROCAL_LCM_URL or the default
    std::string as_run;   // "" = the stored run id
    double speed = 1.0;   // [1] recorded seconds per wall second
    bool max = false;     // as fast as the consumers keep up (flow control)
    process::SourceFlowOptions flow = process::SourceFlowOptions::Defaults();  // with max
    static ReplayOptions Defaults() { return {}; }
};

class ReplayNode {
public:
    // Throws when the database cannot be opened or the run is unknown, BusError when LCM cannot.
    explicit ReplayNode(const ReplayOptions& o);
    // Publishes the run (or until SIGINT/SIGTERM). Returns the exit code: 0 when every message
    // went out, 1 after a publish error.
    int Run();
    int64_t published() const { return published_; }
    // The node's bus: tests subscribe to it over memq://.
    bus::Bus& bus() { return bus_; }

private:
    void WaitUntilDue(int64_t recv_utime);
    void WaitForRoom(int64_t recv_utime);  // max: until the consumers have room (flow control)

    ReplayOptions options_;
    std::unique_ptr<db::Db> db_;
    db::ReplayReader reader_;
    bus::Bus bus_;
    std::unique_ptr<flow::FlowSource> flow_;  // max
    std::chrono::steady_clock::time_point wall0_{};
    int64_t recv0_ = -1;
    int64_t published_ = 0;
};

}  // namespace gyrocal::replay
