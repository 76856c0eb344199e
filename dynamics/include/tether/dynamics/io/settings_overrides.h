// Values a front end puts in place of a scene's simulation and stabilization settings (the command line's
// --duration, --step, --integrator, --alpha, --beta, --solver and --stabilization; the Python module's keyword
// arguments of the same names), validated the same way for both, each with a message naming it.
#pragma once

#include <optional>
#include <string>

#include "tether/dynamics/model/model.h"

namespace tether {

struct SettingsOverrides {
  std::optional<double> duration, step, alpha, beta;  // s, s, 1/s, 1/s^2
  std::optional<std::string> integrator, solver, stabilization;

  // Applies the values given to the model. A setting is named `prefix` + its name in messages ("--step" on the
  // command line, "step" in Python). Alpha or beta selects the baumgarte method; the one not given keeps the
  // value of the default rule at the final integrator and step (default_gains.h). Throws InputError.
  void Apply(Model<double>* model, const std::string& prefix) const;
};

}  // namespace tether
