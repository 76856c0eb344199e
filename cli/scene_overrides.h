// Command-line flags that override a scene's simulation and stabilization settings, shared by the commands
// that run scenes. Each value is validated (settings_overrides.h) with a message naming its flag.
#pragma once

#include <CLI/CLI.hpp>

#include "tether/dynamics/io/settings_overrides.h"

namespace tether::cli {

struct SceneOverrides : SettingsOverrides {
  // `gains`: whether the command takes --alpha, --beta and --stabilization (tune does not: it chooses them).
  void Register(CLI::App* app, bool gains = true);
  // Applies the flags to the model; throws InputError naming the flag at fault.
  void Apply(Model<double>* model) const { SettingsOverrides::Apply(model, "--"); }
};

}  // namespace tether::cli
