#pragma once
#include <CLI/CLI.hpp>
#include <functional>

namespace gyrocal::cli {
// `gyrocal spy`: lcm-spy with the project's types. Debian's /usr/bin/lcm-spy passes -Xincgc,
// which Java 17 rejects, so this starts lcm.spy.Spy itself.
void AddSpyCommand(CLI::App& app, std::function<int()>& action);
}  // namespace gyrocal::cli
