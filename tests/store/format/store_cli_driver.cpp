// Stands in for the lead's `gyrocal` main: its parse/run sequence (ParseAndRun) around
// AddStoreCommands, so the store commands are tested as users will run them.
#include <CLI/CLI.hpp>
#include <functional>

#include "tools/cli/cmd_store.hpp"
#include "tools/cli/command.hpp"

int main(int argc, char** argv) {
    CLI::App app{"store command test driver"};
    app.require_subcommand(1);
    std::function<int()> action;
    AddStoreCommands(app, action);
    return gyrocal::cli::ParseAndRun(app, argc, argv, action);
}
