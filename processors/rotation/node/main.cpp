// gyrocal-rotation: sensitivity from encoder-measured rotations. See rotation_node.hpp for the
// threads and rotation_estimator.hpp for the windows and the uncertainty.
#include <CLI/CLI.hpp>

#include "lcmtypes/process/process_main.hpp"
#include "processors/motion/node/motion_options.hpp"
#include "processors/rotation/node/rotation_node.hpp"

namespace {

void AddOptions(CLI::App& app, gyrocal::rotation::node::RotationOptions& o) {
    auto& e = o.estimator;
    gyrocal::motion::node::AddInputOptions(app, o.lcm_url, o.sensors, o.encoder_id);
    app.add_option("--guard-s", e.guard_s, "[s] between the move and each rest window, 0..60");
    app.add_option("--rest-s", e.rest_s,
                   "[s] each rest window (offset before and after), 0.05..600");
    app.add_option("--min-rest-fraction", e.min_rest_fraction,
                   "[0.1..1] of --rest-s a rest window must cover");
    app.add_option("--min-angle-deg", e.min_angle_deg, "[deg] smaller moves are rejected");
    app.add_option("--max-move-s", e.max_move_s, "[s] longer moves are rejected");
    app.add_option("--encoder-stale-s", e.encoder_stale_s,
                   "[s] finish a point without the encoder once samples are this far past it");
    app.add_option("--slip-alpha", e.slip_alpha,
                   "false alarms per move of the encoder-slip check, (0, 0.1)");
    app.add_option("--min-slip-deg", e.min_slip_deg,
                   "[deg] the gyro's and the encoder's angles may part this much before a slip is "
                   "called, 0..90");
    gyrocal::motion::node::AddMoveOptions(app, o.move, "the move is over");
}

}  // namespace

int main(int argc, char** argv) {
    return gyrocal::process::NodeMain<gyrocal::rotation::node::RotationNode>(
        argc, argv, "gyrocal-rotation",
        "gyrocal-rotation: sensitivity from encoder-measured rotations, per sensor.\n"
        "Subscribes GYRO_*, ENCODER, RUN_EVENT; publishes SENSITIVITY_<id> (one per move,\n"
        "after the rest window that follows it), STATUS.",
        AddOptions);
}
