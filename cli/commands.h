// Every subcommand of the `tether` front end, registered on one CLI11 app (main.cc, and the command-line fuzzer).
#pragma once

#include <CLI/CLI.hpp>
#include <memory>
#include <string>
#include <vector>

#include "command.h"

namespace tether::cli {

// The subcommands in the order `tether --help` lists them; --version too.
std::vector<std::unique_ptr<Command>> RegisterCommands(CLI::App* app, const std::string& version);

// For a first argument that names no subcommand: "unknown command 'simulat' (did you mean 'simulate'?; the commands
// are ...)"; empty when it names one. (CLI11 answers such a word with "A subcommand is required".)
std::string UnknownCommand(CLI::App& app, const std::string& word);

// After a parse that left arguments over (CLI11's ExtrasError, which lists them last first): each in the command
// line's order, a flag with the command's nearest one ("simulate: unknown flag '--stpe' (did you mean
// '--step'?); unexpected argument 'extra'"); empty when none is left.
std::string UnexpectedArguments(CLI::App& app, int argc, char** argv);

}  // namespace tether::cli
