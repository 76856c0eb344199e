// Checks of the command line's own values, made before any work starts.
#pragma once

#include <string>
#include <vector>

namespace tether::cli {

// Upper bounds of the counts users give: far above any sensible use, low enough that no count overflows and
// no request is accepted that could not finish (a run's steps are bounded by kMaxSteps, model.h).
inline constexpr int kMaxSamples = 1000;          // tune --samples
inline constexpr int kMaxEvaluations = 1000000;   // --max-evaluations
inline constexpr int kMaxSegments = 100000;       // identify/fit --segments
inline constexpr int kMaxThreads = 1024;          // study --threads

// `value` of `flag` as a whole number in [low, high], or InputError naming the flag.
int CheckCount(int value, int low, int high, const std::string& flag);

// Output paths given with their flags (empty paths are skipped): none may be one of the run's `inputs` or
// unwritable (CheckOutputPath, output_file.h); a figure path must end in .png or .svg.
struct OutputFlag {
  std::string path, flag;
  bool figure = false;
};
void CheckOutputs(const std::vector<OutputFlag>& outputs, const std::vector<std::string>& inputs);

}  // namespace tether::cli
