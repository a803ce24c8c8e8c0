#pragma once
// A detected plateau as the PLATEAU_<id> message: what gyrocal-plateau publishes and what the
// virtual lab (tests/support/virtual_lab) hands to the fitter core in its place. Only the
// generated message struct, no LCM runtime (so kept out of the pure gyrocal_plateau).
#include <string>

#include "gyrocal/plateau_t.hpp"
#include "processors/plateau/plateau_detector.hpp"

namespace gyrocal::plateau::node {

plateau_t ToMessage(const std::string& sensor_id, const plateau::Plateau& p);

}  // namespace gyrocal::plateau::node
