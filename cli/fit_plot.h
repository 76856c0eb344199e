// Plots of an identification or a fit: every observed column of every recording (dots) and every constrained
// column's bound (a triangle at its time, pointing the way the column must lie) against the motion simulated with
// the estimates (line), one panel per column, drawn by matplotlib (Debian's python3-matplotlib).
#pragma once

#include <string>
#include <vector>

#include "tether/autodiff/observations.h"
#include "tether/dynamics/model/model.h"
#include "tether/tuning/identification.h"

namespace tether::cli {

// A scheduled effect the fit may have set, with its unit in its label: a motor's torque or force, and each
// component of a scheduled force or torque that is not zero throughout (interpolated linearly between knots).
struct ScheduledEffect {
  std::string label;
  std::vector<double> times, values;
};
std::vector<ScheduledEffect> ScheduledEffects(const Model<double>& model);

// The unit of a trajectory column, by the suffix tether gives it (docs/contract.md's columns); empty for a
// quaternion's components.
std::string ColumnUnit(const std::string& name);

// Writes the PNG (or SVG, by the file name) at `path`, or throws InputError saying what is missing; nothing is
// left at `path` on failure.
void PlotFit(const Model<double>& fitted, const std::vector<Observations>& recordings,
             const std::vector<InequalityTarget>& constraints, const std::string& path);

}  // namespace tether::cli
