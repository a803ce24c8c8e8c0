#pragma once
// gyrocal-fitter's LCM node: PLATEAU_*, SENSITIVITY_*, NOISE_*, RUN_EVENT in; COEFFS_<id>,
// FIT_<id> and STATUS out; with the closed loop (the default) also GYRO_*, ENCODER, POWER_* and
// CHAMBER_STATE in and, at the stop, each unit's final set fitted on every still sample
// (COEFFS_<id> source "closed-loop", FIT_<id>, ANALYSIS_<id>) after its plateau set.
// Threads: the node's and the fit worker's (fit_worker.hpp). Bus::Handle dispatches on the Run()
// thread; each handler guards, calls FitterCore (fitter_core.hpp, all the decisions) or bins the
// sample (ramp_fitter.hpp), and publishes what it returns: every report right after its
// coefficient set. A fit on every still bin is handed to the worker; its results are published
// from the Run() thread between dispatches. SIGINT/SIGTERM end RunLoop.
#include <CLI/CLI.hpp>
#include <functional>
#include <optional>
#include <string>

#include "lcmtypes/bus/bus.hpp"
#include "lcmtypes/process/status.hpp"
#include "processors/fitter/fitter_core.hpp"
#include "processors/fitter/node/fit_worker.hpp"
#include "processors/fitter/ramp_fitter.hpp"

namespace gyrocal::fitter::node {

struct FitterOptions {
    std::string lcm_url;  // "" = $GYROCAL_LCM_URL or the default
    fitter::CoreOptions core;
    std::string method = "auto";
    std::string mode = "plateau";  // plateau (FitterCore) | ramp (RampFitter, ramp_fitter.hpp)
    fitter::RampFitterOptions ramp;
    // Plateau mode: also fit every still sample at the stop (the run's final set, beside the
    // plateau set); the seed's 3-point procedure keeps its own method without it.
    bool closed_loop = true;
    static FitterOptions Defaults() { return {}; }
};

// Registers the fitter's options on `app`; the returned validator completes and checks them.
std::function<std::string()> AddFitterOptions(CLI::App& app, FitterOptions& o);

// The fit on every still bin on the bus, for either node: it subscribes the samples this fit
// reads (GYRO_*, ENCODER, POWER_*, CHAMBER_STATE) into `fitter` on the node's thread, hands the
// fits due to its worker, and publishes their results (set, report, analysis) when Publish() is
// called, on the node's thread.
class StillFitChannel {
public:
    StillFitChannel(bus::Bus& bus, process::StatusReporter& status, fitter::RampFitter& fitter);
    void Submit(std::vector<fitter::FitJob> jobs);
    // Publishes the results done so far; returns how many.
    size_t Publish();
    FitWorker& worker() { return worker_; }

private:
    bus::Bus& bus_;
    process::StatusReporter& status_;
    fitter::RampFitter& fitter_;
    FitWorker worker_;
    int64_t now_utime_ = 0;
    int64_t sets_published_ = 0;
    double max_fit_s_ = 0.0;
};

class FitterNode {
public:
    explicit FitterNode(const FitterOptions& o);  // throws BusError when LCM cannot open
    void Run();
    bus::Bus& bus() { return bus_; }  // tests publish into it over memq://
    const process::StatusReporter& status() const { return status_; }
    // One dispatch round and the closed loop's results (tests).
    void HandleFor(int timeout_ms);

private:
    void Apply(const fitter::CoreOutput& out);
    void UpdateStatus();

    bus::Bus bus_;
    process::StatusReporter status_;
    fitter::FitterCore core_;
    std::optional<fitter::RampFitter> loop_;  // the closed loop (FitterOptions::closed_loop)
    std::optional<StillFitChannel> loop_channel_;
};

// gyrocal-fitter --mode ramp: GYRO_*, ENCODER, POWER_*, CHAMBER_STATE, SENSITIVITY_*, RUN_EVENT
// in; COEFFS_<id>, FIT_<id>, ANALYSIS_<id> and STATUS out. Threads as above: the handlers bin,
// the worker fits (on data time, and at the stop), Run()'s thread publishes.
class RampFitterNode {
public:
    explicit RampFitterNode(const FitterOptions& o);  // throws BusError when LCM cannot open
    void Run();
    bus::Bus& bus() { return bus_; }  // tests publish into it over memq://
    void HandleFor(int timeout_ms);   // one dispatch round and the fits done (tests)
    StillFitChannel& channel() { return *channel_; }

private:
    bus::Bus bus_;
    process::StatusReporter status_;
    fitter::RampFitter fitter_;
    std::optional<StillFitChannel> channel_;
};

}  // namespace gyrocal::fitter::node
