#pragma once
// gyrocal-fitter's LCM node: PLATEAU_*, SENSITIVITY_*, NOISE_*, RUN_EVENT in; COEFFS_<id>,
// FIT_<id> and STATUS out.
// Threads: one. Bus::Handle dispatches on the Run() thread; each handler guards, calls
// FitterCore (fitter_core.hpp, all the decisions) and publishes what it returns: every report
// right after its coefficient set. SIGINT/SIGTERM end RunLoop.
#include <CLI/CLI.hpp>
#include <functional>
#include <string>

#include "bus/bus.hpp"
#include "runtime/status.hpp"
#include "fitter_core.hpp"
#include "ramp_fitter.hpp"

namespace gyrocal {

struct FitterOptions {
    std::string lcm_url;  // "" = $GYROCAL_LCM_URL or the default
    fitter::CoreOptions core;
    std::string method = "auto";
    std::string mode = "plateau";  // plateau (FitterCore) | ramp (RampFitter, ramp_fitter.hpp)
    fitter::RampFitterOptions ramp;
    static FitterOptions Defaults() { return {}; }
};

// Registers the fitter's options on `app`; the returned validator completes and checks them.
std::function<std::string()> AddFitterOptions(CLI::App& app, FitterOptions& o);

class FitterNode {
public:
    explicit FitterNode(const FitterOptions& o);  // throws BusError when LCM cannot open
    void Run();
    Bus& bus() { return bus_; }  // tests publish into it over memq://
    const StatusReporter& status() const { return status_; }

private:
    void Apply(const fitter::CoreOutput& out);
    void UpdateStatus();

    Bus bus_;
    StatusReporter status_;
    fitter::FitterCore core_;
};

// gyrocal-fitter --mode ramp: GYRO_*, ENCODER, SENSITIVITY_*, RUN_EVENT in; COEFFS_<id>, FIT_<id>
// and STATUS out. One thread as above; a fit (RampFitter, on data time or at the stop) runs in
// the handler that makes it due.
class RampFitterNode {
public:
    explicit RampFitterNode(const FitterOptions& o);  // throws BusError when LCM cannot open
    void Run();

private:
    void Publish(const std::vector<fitter::RampFitResult>& results);

    Bus bus_;
    StatusReporter status_;
    fitter::RampFitter fitter_;
    int64_t now_utime_ = 0;
    int64_t sets_published_ = 0;
};

}  // namespace gyrocal
