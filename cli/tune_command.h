// `tether tune SCENE [--objective reference|drift] [--optimizer NAME] [--samples N] [--max-evaluations N]
//                    [--write-scene OUT.json]` (plus the scene overrides of `simulate`): tunes the Baumgarte
// gains for the scene's integrator and step and prints JSON with alpha, beta, omega, zeta, the objective, the
// stability margin and a comparison with presets; a readable summary goes to stderr.
#pragma once

#include <memory>

#include "command.h"

namespace tether::cli {

std::unique_ptr<Command> MakeTuneCommand(CLI::App* parent);

}  // namespace tether::cli
