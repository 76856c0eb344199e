// `tether identify SCENE --data OBS.csv [--data ...] --param PTR [--param ...] [--bound PTR=LO:HI ...]
//                  [--segments K] [--loss huber:D|cauchy:D] [--optimizer NAME] [--max-evaluations N] [-o OUT.json]
//                  [--plot FILE.png]`
// `tether fit SCENE --data TARGETS.csv --param PTR ... [--smooth W] [...the same options]`
// (plus the scene overrides of `simulate`): estimate parameters from recordings (identify) or make a scene meet
// targets (fit), and print JSON: parameters, standard_deviation, correlation, initial_cost, final_cost,
// residual statistics and warnings; -o writes the scene with the estimates in place.
#pragma once

#include <memory>

#include "command.h"

namespace tether::cli {

std::unique_ptr<Command> MakeIdentifyCommand(CLI::App* parent);
std::unique_ptr<Command> MakeFitCommand(CLI::App* parent);

}  // namespace tether::cli
