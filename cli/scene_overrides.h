// Command-line flags that override a scene's simulation and stabilization settings, shared by the commands
// that run scenes. Each value is validated with a message naming its flag.
#pragma once

#include <CLI/CLI.hpp>
#include <optional>
#include <string>

#include "tether/dynamics/model.h"

namespace tether::cli {

struct SceneOverrides {
  std::optional<double> duration, step, alpha, beta;
  std::optional<std::string> integrator, solver, stabilization;

  void Register(CLI::App* app);
  // Applies the flags to the model; throws InputError naming the flag at fault.
  void Apply(Model<double>* model) const;
};

}  // namespace tether::cli
