// gyrocal-rotation: sensitivity from encoder-measured rotations. See rotation_node.hpp for the
// threads and rotation_estimator.hpp for the windows and the uncertainty.
#include <CLI/CLI.hpp>

#include "motion/motion_options.hpp"
#include "runtime/process_main.hpp"
#include "rotation_node.hpp"

namespace {

void AddOptions(CLI::App& app, gyrocal::RotationOptions& o) {
    auto& e = o.estimator;
    gyrocal::motion::AddInputOptions(app, o.lcm_url, o.sensors, o.encoder_id);
    app.add_option("--guard-s", e.guard_s, "[s] between the move and each rest window, 0..60")
        ->capture_default_str();
    app.add_option("--rest-s", e.rest_s,
                   "[s] each rest window (offset before and after), 0.05..600")
        ->capture_default_str();
    app.add_option("--min-rest-fraction", e.min_rest_fraction,
                   "[0.1..1] of --rest-s a rest window must cover")
        ->capture_default_str();
    app.add_option("--min-angle-deg", e.min_angle_deg, "[deg] smaller moves are rejected")
        ->capture_default_str();
    app.add_option("--max-move-s", e.max_move_s, "[s] longer moves are rejected")
        ->capture_default_str();
    app.add_option("--encoder-stale-s", e.encoder_stale_s,
                   "[s] finish a point without the encoder once samples are this far past it")
        ->capture_default_str();
    app.add_option("--slip-alpha", e.slip_alpha,
                   "false alarms per move of the encoder-slip check, (0, 0.1)")
        ->capture_default_str();
    app.add_option("--min-slip-deg", e.min_slip_deg,
                   "[deg] the gyro's and the encoder's angles may part this much before a slip is "
                   "called, 0..90")
        ->capture_default_str();
    gyrocal::motion::AddMoveOptions(app, o.move, "the move is over");
}

}  // namespace

int main(int argc, char** argv) {
    gyrocal::RotationOptions options = gyrocal::RotationOptions::Defaults();
    CLI::App app{
        "gyrocal-rotation: sensitivity from encoder-measured rotations, per sensor.\n"
        "Subscribes GYRO_*, ENCODER, RUN_EVENT; publishes SENSITIVITY_<id> (one per move,\n"
        "after the rest window that follows it), STATUS.",
        "gyrocal-rotation"};
    app.footer(gyrocal::kNodeExitCodes);
    AddOptions(app, options);
    if (auto exit_code = gyrocal::ParseCommandLine(app, argc, argv, "gyrocal-rotation",
                                                   [&] { return options.Validate(); }))
        return *exit_code;
    return gyrocal::RunUntilStopped("gyrocal-rotation",
                                    [&] { gyrocal::RotationNode(options).Run(); });
}
