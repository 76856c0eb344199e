// `tether view SCENE [--data TRAJECTORY.csv [--compare SIMULATED.csv]] -o VIEW.html` (docs/view.md): the page that
// plays the scene's motion, simulated first without --data; with --compare, that simulation beside the recording
// --data gives, drawn as ghosts. Without the viewer in the build (-DTETHER_VIEWER=OFF) it says so, status 2.
#pragma once

#include <memory>

#include "command.h"

namespace tether::cli {

std::unique_ptr<Command> MakeViewCommand(CLI::App* parent);

}  // namespace tether::cli
