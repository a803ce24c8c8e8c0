#pragma once
// The LCM shell around Procedure: feeds it data time, plateaus and sensitivity points, and
// publishes what it orders (RUN_EVENT, CHAMBER_CMD, TURNTABLE_CMD). A ramp run also hears the
// chamber's air temperature and every unit's coefficient sets (COEFFS_<id>, for its early stop).
#include <functional>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "lcmtypes/bus/bus.hpp"
#include "lcmtypes/process/status.hpp"
#include "processors/model/convert.hpp"
#include "processors/sequencer/procedure.hpp"

namespace gyrocal::sequencer::node {

struct SequencerOptions {
    std::string lcm_url;
    ProcedureOptions procedure;   // sensor_ids empty = discover from GYRO_* channels
    double discover_s = 2.0;      // [s] data time to listen for sensors before starting
    std::string run_id;           // "" = generated from wall time, host and pid
    std::string run_config_json;  // configuration of the whole graph (from the launcher)
    std::string command_line;     // recorded with the run
    static SequencerOptions Defaults();
};

class SequencerNode {
public:
    explicit SequencerNode(SequencerOptions options);
    // Runs until the procedure is done or SIGINT/SIGTERM (which aborts the run, recorded).
    // Returns the exit code: 0 completed, 3 run aborted.
    int Run();
    // Tests drive the node in-process over memq://: they publish into its bus and dispatch with
    // Handle; done() once the procedure has ended.
    bus::Bus& bus() { return bus_; }
    void PublishStatus() { status_.PublishNow(); }
    bool done() const { return procedure_ && procedure_->done(); }

private:
    void OnAnyTime(int64_t utime);
    void Publish(const std::vector<Order>& orders);
    void PublishOrder(const ChamberOrder& c);
    void PublishOrder(const TurntableOrder& t);
    void PublishOrder(const RunEventOrder& r);
    // A message of this run stamped with the data time (commands then take the next id of
    // their kind).
    template <class Msg>
    Msg Stamped() const {
        Msg m{};
        m.utime = now_utime_;
        m.run_id = options_.run_id;
        return m;
    }
    void MaybeStart(int64_t utime);
    void OnCoeffs(const std::string& sensor_id, int64_t utime, const model::CoeffSet& set);

    SequencerOptions options_;
    bus::Bus bus_;
    process::StatusReporter status_;
    std::unique_ptr<Runner> procedure_;
    std::set<std::string> discovered_;
    int64_t first_utime_ = -1;
    int64_t now_utime_ = 0;
    int64_t chamber_cmd_id_ = 0;
    int64_t turntable_cmd_id_ = 0;
    std::string config_json_;
};

}  // namespace gyrocal::sequencer::node
