// Every subcommand of the `tether` front end, registered on one CLI11 app (main.cc, and the command-line fuzzer).
#pragma once

#include <memory>
#include <vector>

#include <CLI/CLI.hpp>

#include "command.h"

namespace tether::cli {

// The subcommands in the order `tether --help` lists them; --version too.
std::vector<std::unique_ptr<Command>> RegisterCommands(CLI::App* app, const std::string& version);

}  // namespace tether::cli
