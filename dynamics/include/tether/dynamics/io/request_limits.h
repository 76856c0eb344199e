// The counts users give to the front ends (the command line's flags, the Python module's arguments), checked the
// same way by both before any work starts.
#pragma once

#include <string>

namespace tether {

// Upper bounds of the counts: far above any sensible use, low enough that no count overflows and no request is
// accepted that could not finish (a run's steps are bounded by kMaxSteps, model.h).
inline constexpr int kMaxSamples = 1000;         // tune's initial states
inline constexpr int kMaxEvaluations = 1000000;  // an optimizer's budget
inline constexpr int kMaxSegments = 100000;      // identify and fit's multiple-shooting segments
inline constexpr int kMaxStarts = 10000;         // fit's starts (--starts)
inline constexpr int kMaxThreads = 1024;         // a study's threads

// `value` given as `what` (a flag or an argument's name) when it is a whole number in [low, high]; InputError
// naming `what` otherwise.
int CheckCount(int value, int low, int high, const std::string& what);

}  // namespace tether
