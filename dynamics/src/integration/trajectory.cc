#include "tether/dynamics/integration/trajectory.h"

namespace tether {

template <typename T>
Trajectory<T> Record(const Model<T>& model, const RunOptions& options, RecordWhat what) {
  Trajectory<T> out;
  out.report = Simulate<T>(model, options, [&](const Sample<T>& s) {
    if (what == RecordWhat::kOutputs ? !s.output : s.stop < 0) return;
    out.t.push_back(s.t);
    out.q.push_back(s.q);
    out.v.push_back(s.v);
    out.constraint_error.push_back(s.constraint_error);
    out.energy.push_back(s.energy);
    out.coordinates.push_back(s.coordinates);
  });
  return out;
}

template Trajectory<double> Record<double>(const Model<double>&, const RunOptions&, RecordWhat);
template Trajectory<Jet> Record<Jet>(const Model<Jet>&, const RunOptions&, RecordWhat);

}  // namespace tether
