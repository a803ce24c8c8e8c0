#pragma once
// gyrocal-sequencer's command line, apart from the node so that the node knows no CLI11.
#include <CLI/CLI.hpp>
#include <functional>
#include <string>

#include "processors/sequencer/node/sequencer_node.hpp"

namespace gyrocal::sequencer::node {

// Registers gyrocal-sequencer's options on `app`; the returned validator resolves the profile and
// checks every option ("" or the problem, naming the option). `o` must outlive the validator.
std::function<std::string()> AddSequencerOptions(CLI::App& app, SequencerOptions& o);

}  // namespace gyrocal::sequencer::node
