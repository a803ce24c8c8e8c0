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
#include "bus/status.hpp"
#include "fitter_core.hpp"

namespace gyrocal {

struct FitterOptions {
    std::string lcm_url;  // "" = $GYROCAL_LCM_URL or the default
    fitter::CoreOptions core;
    std::string method = "auto";
    static FitterOptions Defaults() { return {}; }
};

// Registers the fitter's options on `app`; the returned validator completes and checks them.
std::function<std::string()> AddFitterOptions(CLI::App& app, FitterOptions& o);

class FitterNode {
public:
    explicit FitterNode(const FitterOptions& o);  // throws BusError when LCM cannot open
    void Run();

private:
    template <class F>
    void Guarded(F&& f);
    void Apply(const fitter::CoreOutput& out);
    void UpdateStatus();

    Bus bus_;
    StatusReporter status_;
    fitter::FitterCore core_;
};

}  // namespace gyrocal
