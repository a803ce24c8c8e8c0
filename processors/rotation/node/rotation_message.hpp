#pragma once
// A rotation's sensitivity point as the SENSITIVITY_<id> message: what gyrocal-rotation publishes
// and what the virtual lab (tests/support/virtual_lab) hands to the fitter core in its place.
// Only the generated message struct, no LCM runtime (so kept out of the pure gyrocal_rotation).
#include <string>

#include "gyrocal/sensitivity_point_t.hpp"
#include "processors/rotation/rotation_estimator.hpp"

namespace gyrocal::rotation::node {

// run_id: the run in force when the point was made ("" = none).
sensitivity_point_t ToMessage(const std::string& sensor_id, const std::string& run_id,
                              const rotation::Point& p);

}  // namespace gyrocal::rotation::node
