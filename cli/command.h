// A subcommand of the `tether` front end: it registers its flags on a CLI11 subcommand and runs when chosen.
// Run() returns the exit status (0 success, 1 a failed run) or throws InputError (status 2).
#pragma once

#include <CLI/CLI.hpp>

namespace tether::cli {

class Command {
 public:
  virtual ~Command() = default;
  virtual CLI::App* app() const = 0;
  virtual int Run() = 0;
};

}  // namespace tether::cli
