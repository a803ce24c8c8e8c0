// gyrocal-plateau: per-sensor stability (plateau) detector. See plateau_node.hpp for the threads
// and plateau_detector.hpp for the criterion and its defaults.
#include <CLI/CLI.hpp>

#include "lcmtypes/process/process_main.hpp"
#include "processors/motion/node/motion_options.hpp"
#include "processors/plateau/node/plateau_node.hpp"

namespace {

void AddOptions(CLI::App& app, gyrocal::plateau::node::PlateauOptions& o) {
    auto& d = o.detector;
    gyrocal::motion::node::AddInputOptions(app, o.lcm_url, o.sensors, o.encoder_id);
    app.add_option("--window-s", d.window_s,
                   "[s] sliding window of the stability criterion, 1..3600");
    app.add_option("--slope-max-c-per-min", d.slope_max_c_per_min,
                   "[degC/min] max |temperature slope| over the window");
    app.add_option("--scatter-max-c", d.scatter_max_c,
                   "[degC] max rms scatter about the window's line");
    app.add_option("--min-stable-s", d.min_stable_s,
                   "[s] criterion held this long before averaging");
    app.add_option("--average-s", d.average_s, "[s] of still samples averaged per plateau");
    app.add_option("--sem-batches", d.sem_batches,
                   "batches for the batch-means standard error, 4..1000");
    app.add_option("--rearm-band-c", d.rearm_band_c,
                   "[degC] after a plateau, leaving it by more re-arms (data without a chamber)");
    app.add_option("--min-move-fraction", d.min_move_fraction,
                   "[0..1] of a setpoint change the temperature must move before it is judged");
    app.add_option("--leave-factor", d.leave_factor, "thresholds x this abort an average, >= 1");
    app.add_option("--state-period-s", d.state_period_s,
                   "[s] of data time between STABILITY_<id> reports");
    app.add_option("--motion-guard-s", o.motion_guard_s,
                   "[s] samples this close to table motion are excluded");
    app.add_option("--encoder-stale-s", o.encoder_stale_s,
                   "[s] classify samples without the encoder once their stream is this far ahead");
    gyrocal::motion::node::AddMoveOptions(app, o.move, "at rest");
    app.add_option("--noise-period-s", o.noise_period_s,
                   "[s] of data time between NOISE_<id> (Allan deviation) messages");
    app.add_option("--noise-quiet-slope-c-per-min", o.noise.quiet_slope_c_per_min,
                   "[degC/min] still stretches count for the Allan deviation where the "
                   "temperature moves less than this");
    app.add_option("--noise-min-segment-s", o.noise.min_segment_s,
                   "[s] shorter quiet stretches are not used for the Allan deviation");
}

}  // namespace

int main(int argc, char** argv) {
    return gyrocal::process::NodeMain<gyrocal::plateau::node::PlateauNode>(
        argc, argv, "gyrocal-plateau",
        "gyrocal-plateau: stability (plateau) detector per sensor.\n"
        "Subscribes GYRO_*, ENCODER, CHAMBER_STATE, RUN_EVENT; publishes PLATEAU_<id>,\n"
        "STABILITY_<id>, NOISE_<id> (Allan deviation of the still stretches), STATUS.",
        AddOptions);
}
