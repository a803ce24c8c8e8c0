#pragma once
#include <CLI/CLI.hpp>
#include <functional>

#include "tools/supervisor/supervisor.hpp"

namespace gyrocal::cli {
// `gyrocal calibrate`: starts the whole process graph as separate OS processes, shows progress,
// stops everything on completion or Ctrl-C, prints the coefficient table. services: what the run
// needs of the store (the acceptance step, a restarted process's state), built by main.
void AddCalibrateCommand(CLI::App& app, std::function<int()>& action,
                         supervisor::StoreServices services);
}  // namespace gyrocal::cli
