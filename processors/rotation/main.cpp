// gyrocal-rotation: sensitivity from encoder-measured rotations. See rotation_node.hpp for the
// threads and rotation_estimator.hpp for the windows and the uncertainty.
#include <CLI/CLI.hpp>
#include <iostream>

#include "bus/shutdown.hpp"
#include "rotation_node.hpp"

namespace {

constexpr const char* kExitCodes =
    "Exit codes: 0 normal stop (SIGINT/SIGTERM), 1 runtime failure (e.g. LCM cannot open),\n"
    "            2 bad options.";

void AddOptions(CLI::App& app, gyrocal::RotationOptions& o) {
    auto& e = o.estimator;
    app.add_option("--lcm-url", o.lcm_url,
                   "LCM provider URL (default: $GYROCAL_LCM_URL, else udpm default)");
    app.add_option("--sensors", o.sensors, "accept only these sensor ids (default: every valid id)")
        ->delimiter(',');
    app.add_option("--encoder-id", o.encoder_id, "encoder_id of the turntable encoder")
        ->capture_default_str();
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
    app.add_option("--start-threshold-counts", o.move.start_threshold_counts,
                   "[count] the table leaves rest when it moves more than this")
        ->capture_default_str();
    app.add_option("--settle-band-counts", o.move.settle_band_counts,
                   "[count] encoder dither tolerated at rest")
        ->capture_default_str();
    app.add_option("--settle-s", o.move.settle_s,
                   "[s] within the band this long = the move is over")
        ->capture_default_str();
}

}  // namespace

int main(int argc, char** argv) {
    gyrocal::RotationOptions options = gyrocal::RotationOptions::Defaults();
    CLI::App app{
        "gyrocal-rotation: sensitivity from encoder-measured rotations, per sensor.\n"
        "Subscribes GYRO_*, ENCODER, RUN_EVENT; publishes SENSITIVITY_<id> (one per move,\n"
        "after the rest window that follows it), STATUS.",
        "gyrocal-rotation"};
    app.footer(kExitCodes);
    AddOptions(app, options);
    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        std::cerr << "gyrocal-rotation: " << e.what() << " (see --help)\n";
        return 2;
    }
    if (std::string err = options.Validate(); !err.empty()) {
        std::cerr << "gyrocal-rotation: " << err << "\n";
        return 2;
    }
    try {
        gyrocal::InstallStopHandlers();
        gyrocal::RotationNode node(options);
        node.Run();
    } catch (const std::exception& e) {
        std::cerr << "gyrocal-rotation: " << e.what() << "\n";
        return 1;
    }
    return 0;
}
