// Stands in for the lead's `gyrocal` main: exactly its parse/run sequence around
// AddStoreCommands, so the store commands are tested as users will run them.
#include <CLI/CLI.hpp>
#include <functional>

#include "cmd_store.hpp"

int main(int argc, char** argv) {
    CLI::App app{"store command test driver"};
    app.require_subcommand(1);
    std::function<int()> action;
    AddStoreCommands(app, action);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        const int rc = app.exit(e);
        return rc == 0 ? 0 : 2;
    }
    return action ? action() : 2;
}
