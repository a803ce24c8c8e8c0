#pragma once
// What the `gyrocal` commands share: how the command line is parsed and the chosen command run
// (main.cpp, and the store commands' test driver), and a command's last-resort failure line.
// Header only: each command library includes it without another link.
#include <CLI/CLI.hpp>
#include <exception>
#include <functional>
#include <ostream>
#include <string>

#include "lcmtypes/process/process_main.hpp"

namespace gyrocal::cli {

// Parses argv, where the chosen subcommand sets `action`, then runs it and returns its exit code;
// 0 after --help or --version; 2 for a bad option or no command (CLI11's message on stderr).
// With GYROCAL_CHECK_ONLY=1 (runtime/process_main.hpp) it stops after the checks: 0, nothing run.
inline int ParseAndRun(CLI::App& app, int argc, char** argv, const std::function<int()>& action) {
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        const int rc = app.exit(e);
        return rc == 0 ? 0 : 2;
    }
    if (!action) return 2;
    return process::CheckOnly() ? 0 : action();  // GYROCAL_CHECK_ONLY=1: the command line is valid
}

// Runs a command's `body` and returns its exit code; an exception that escapes it (the database,
// a file, the analysis) is the command's failure: "<prefix><what>" on `err`, exit 1.
inline int FailOnThrow(std::ostream& err, const std::string& prefix,
                       const std::function<int()>& body) {
    try {
        return body();
    } catch (const std::exception& e) {
        err << prefix << e.what() << "\n";
        return 1;
    }
}

}  // namespace gyrocal::cli
