#pragma once
// The options gyrocal-plateau and gyrocal-rotation share, with the same names, defaults, help
// texts and checks in both: where the samples and the encoder come from, and the move detector.
// Whether --help shows their defaults is the app's choice (the processes' NodeMain shows them).
#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "processors/motion/table_motion.hpp"

namespace gyrocal::motion::node {

// --lcm-url, --sensors, --encoder-id.
void AddInputOptions(CLI::App& app, std::string& lcm_url, std::vector<std::string>& sensors,
                     std::string& encoder_id);

// --start-threshold-counts, --settle-band-counts, --settle-s. `settled` ends the help of
// --settle-s: what the table staying within the band that long means to the process.
void AddMoveOptions(CLI::App& app, MoveDetectorConfig& move, const std::string& settled);

// "" when --sensors and --encoder-id are valid, else a one-line error naming the option.
std::string ValidateInput(const std::vector<std::string>& sensors, const std::string& encoder_id);

// The libraries name a config field first ("window_s must be ..."); the option is that name
// with dashes ("--window-s must be ...").
std::string AsOption(std::string message);

}  // namespace gyrocal::motion::node
