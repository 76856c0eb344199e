// `tether check SCENE [--json]`: degrees of freedom, constraint rank, redundant constraints, the initial
// violation and the conditioning of a scene's constraints at its initial state (scene_check.h).
#pragma once

#include <memory>

#include "command.h"

namespace tether::cli {

std::unique_ptr<Command> MakeCheckCommand(CLI::App* parent);

}  // namespace tether::cli
