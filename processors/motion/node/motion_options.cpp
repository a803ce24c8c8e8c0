#include "processors/motion/node/motion_options.hpp"

#include "lcmtypes/channels/channels.hpp"

namespace gyrocal::motion::node {

void AddInputOptions(CLI::App& app, std::string& lcm_url, std::vector<std::string>& sensors,
                     std::string& encoder_id) {
    app.add_option("--lcm-url", lcm_url,
                   "LCM provider URL (default: $GYROCAL_LCM_URL, else udpm default)");
    app.add_option("--sensors", sensors, "accept only these sensor ids (default: every valid id)")
        ->delimiter(',')
        ->default_str("");  // the help says what none means; "[]" would not
    app.add_option("--encoder-id", encoder_id, "encoder_id of the turntable encoder");
}

void AddMoveOptions(CLI::App& app, MoveDetectorConfig& move, const std::string& settled) {
    app.add_option("--start-threshold-counts", move.start_threshold_counts,
                   "[count] the table leaves rest when it moves more than this");
    app.add_option("--settle-band-counts", move.settle_band_counts,
                   "[count] encoder dither tolerated at rest");
    app.add_option("--settle-s", move.settle_s, "[s] within the band this long = " + settled);
}

std::string ValidateInput(const std::vector<std::string>& sensors, const std::string& encoder_id) {
    if (std::string e = channels::ValidateSensorIds(sensors, "--sensors"); !e.empty()) return e;
    if (encoder_id.empty()) return "--encoder-id must not be empty";
    return "";
}

std::string AsOption(std::string message) {
    const size_t end = message.find(' ');
    for (size_t i = 0; i < end && i < message.size(); ++i) {
        if (message[i] == '_') message[i] = '-';
    }
    return "--" + message;
}

}  // namespace gyrocal::motion::node
