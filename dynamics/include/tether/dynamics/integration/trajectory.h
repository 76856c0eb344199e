// Trajectory<T>: a run's samples kept in memory, the one recorder that tuning, identification, studies and tests
// read (docs/architecture.md, principle 5). Streaming consumers (the CSV writer) observe Simulate directly instead.
//
// Record keeps the output rows (RunOptions::every, the first and the last) or only the samples at
// RunOptions::stops, with what each consumer needs of a sample: time, q, v, the largest violation, the energy,
// and the joint coordinates.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include "tether/dynamics/integration/simulator.h"

namespace tether {

template <typename T>
struct Trajectory {
  std::vector<double> t;
  std::vector<VecX<T>> q, v;
  std::vector<double> constraint_error;  // m (rad for angle rows)
  std::vector<T> energy;                 // J
  std::vector<VecX<T>> coordinates;      // the named joints' coordinates (joint_coordinates.h's order)
  RunReport report;

  size_t size() const { return t.size(); }

  // The largest violation over the samples (m).
  double LargestViolation() const {
    double worst = 0.0;
    for (double e : constraint_error) worst = std::max(worst, e);
    return worst;
  }
  // max |E - E0| / max(|E0|, 1 J) over the samples.
  double EnergyDrift() const {
    if (energy.empty()) return 0.0;
    const double e0 = Value(energy.front());
    double drift = 0.0;
    for (const T& e : energy) drift = std::max(drift, std::abs(Value(e) - e0));
    return drift / std::max(std::abs(e0), 1.0);
  }
};

enum class RecordWhat { kOutputs, kStops };

// Throws as Simulate does.
template <typename T>
Trajectory<T> Record(const Model<T>& model, const RunOptions& options = {}, RecordWhat what = RecordWhat::kOutputs);

}  // namespace tether
