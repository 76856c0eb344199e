// Checks of the command line's own values, made before any work starts.
#pragma once

#include <string>
#include <vector>

#include "tether/dynamics/io/request_limits.h"  // CheckCount and the limits of counts, shared with Python

namespace tether::cli {

// Output paths given with their flags (empty paths are skipped): none may be one of the run's `inputs` or
// unwritable (CheckOutputPath, output_file.h); a figure path must end in .png or .svg.
struct OutputFlag {
  std::string path, flag;
  bool figure = false;
};
void CheckOutputs(const std::vector<OutputFlag>& outputs, const std::vector<std::string>& inputs);

}  // namespace tether::cli
