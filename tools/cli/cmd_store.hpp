#pragma once
// The store commands of `gyrocal`: runs, show, history, export, fleet, replay (over the database
// the recorder writes). Each sets `action` to a function returning the exit code:
// 0 success, 1 failure (unknown run or sensor, database missing or unreadable, output not
// writable), 2 bad options (CLI11 parse errors, or an option value that does not parse).
#include <CLI/CLI.hpp>
#include <functional>

void AddStoreCommands(CLI::App& app, std::function<int()>& action);
