// `tether simulate SCENE [--duration T] [--step H] [--integrator NAME] [--alpha A] [--beta B] [--every K]
//                        [--solver auto|dense|sparse] [--stabilization METHOD] [-o OUT.csv]`
// Runs a scene and writes its trajectory CSV (to stdout without -o; nothing at all if the run fails).
#pragma once

#include <memory>

#include "command.h"

namespace tether::cli {

std::unique_ptr<Command> MakeSimulateCommand(CLI::App* parent);

}  // namespace tether::cli
