// `tether gradient SCENE --data OBS.csv --param PTR [--param PTR ...] [--method jet|fd]` (plus the scene
// overrides of `simulate`): prints {"loss", "gradient": {PTR: g}, "seconds", "method", "parameters": {PTR: value}}
// as JSON, loss = 1/2 sum over the data's rows and columns of (simulated - observed)^2.
#pragma once

#include <memory>

#include "command.h"

namespace tether::cli {

std::unique_ptr<Command> MakeGradientCommand(CLI::App* parent);

}  // namespace tether::cli
