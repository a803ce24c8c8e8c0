#pragma once
#include <CLI/CLI.hpp>
#include <functional>

namespace gyrocal::cli {
// `gyrocal calibrate`: starts the whole process graph as separate OS processes, shows progress,
// stops everything on completion or Ctrl-C, prints the coefficient table.
void AddCalibrateCommand(CLI::App& app, std::function<int()>& action);
}  // namespace gyrocal::cli
