// A run of a scene file's model from a command: what it throws names the file, an InputError (the scene's initial
// state cannot be assembled) and a divergence alike (its time and constraint kept).
#pragma once

#include <string>

#include "tether/dynamics/model/errors.h"

namespace tether::cli {

template <typename Run>
auto NamingScene(const std::string& scene_path, Run run) -> decltype(run()) {
  try {
    return run();
  } catch (const InputError& e) {
    throw InputError(scene_path + ": " + e.what());
  } catch (const SimulationDiverged& e) {
    throw SimulationDiverged(scene_path + ": " + e.what(), e.time(), e.constraint());
  }
}

}  // namespace tether::cli
