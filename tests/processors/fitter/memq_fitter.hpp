#pragma once
// A fitter node (FitterNode for --mode plateau, RampFitterNode for --mode ramp) in the test's own
// process over memq:// (LCM's in-process provider), with what it publishes collected in order:
// every coefficient set (COEFFS_*) and every fit report (FIT_*). The node tests share it.
#include <vector>

#include "gyrocal/coeff_set_t.hpp"
#include "gyrocal/fit_report_t.hpp"
#include "lcmtypes/bus/bus.hpp"
#include "lcmtypes/channels/channels.hpp"
#include "processors/fitter/node/fitter_node.hpp"
#include "tests/lcmtypes/bus/bus_wait.hpp"

namespace gyrocal::testing {

template <class Node = fitter::node::FitterNode>
struct MemqFitter {
    // `options` with its LCM URL replaced by memq://.
    explicit MemqFitter(
        fitter::node::FitterOptions options = fitter::node::FitterOptions::Defaults())
        : node(OverMemq(options)), bus(node.bus()) {
        CollectInto(bus, channels::AllSensors(channels::kCoeffsPrefix), coeffs);
        CollectInto(bus, channels::AllSensors(channels::kFitPrefix), reports);
    }
    MemqFitter(const MemqFitter&) = delete;  // the subscriptions hold the vectors' addresses
    MemqFitter& operator=(const MemqFitter&) = delete;

    static fitter::node::FitterOptions OverMemq(fitter::node::FitterOptions o) {
        o.lcm_url = "memq://";
        return o;
    }

    Node node;
    ::gyrocal::bus::Bus& bus;
    std::vector<coeff_set_t> coeffs;
    std::vector<fit_report_t> reports;
};

}  // namespace gyrocal::testing
