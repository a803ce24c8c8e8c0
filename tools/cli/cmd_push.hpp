#pragma once
// `gyrocal push` (a station's runs to the lab's central PostgreSQL database) and `gyrocal central`
// (create or migrate the central schema, grant a role, show its state). Each sets `action` to a
// function returning the exit code: 0 success, 1 failure (one line on stderr: the station file,
// the centre, a run), 2 bad options.
#include <CLI/CLI.hpp>
#include <functional>

namespace gyrocal::cli {

void AddPushCommands(CLI::App& app, std::function<int()>& action);

}  // namespace gyrocal::cli
