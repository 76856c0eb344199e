#include <cmath>
#include <map>
#include <string>

#include "tether/autodiff/observations.h"
#include "tether/dynamics/integration/simulator.h"
#include "tether/dynamics/io/trajectory_columns.h"
#include "tether/dynamics/model/errors.h"
#include "tether/viewer/view.h"

namespace tether {
namespace {

// Body b's pose [x, y, z, qw, qx, qy, qz] at configuration q.
void AppendPose(const Model<double>& model, const VecX<double>& q, int b, std::vector<double>* pose) {
  const Body<double>& body = model.bodies[b];
  for (int k = 0; k < 3; ++k) pose->push_back(k < model.dimension ? q[body.q_offset + k] : 0.0);
  if (body.kind == BodyKind::kRigid3d) {  // normalised: a recording's quaternion may not be
    const Vec4<double> r = q.segment<4>(body.q_offset + 3).normalized();
    pose->insert(pose->end(), {r[0], r[1], r[2], r[3]});
  } else if (body.kind == BodyKind::kPlanar) {
    const double half = 0.5 * q[body.q_offset + 2];
    pose->insert(pose->end(), {std::cos(half), 0.0, 0.0, std::sin(half)});
  } else {
    pose->insert(pose->end(), {1.0, 0.0, 0.0, 0.0});
  }
}

std::vector<double> Poses(const Model<double>& model, const VecX<double>& q) {
  std::vector<double> pose;
  for (size_t b = 0; b < model.bodies.size(); ++b) AppendPose(model, q, static_cast<int>(b), &pose);
  return pose;
}

// Whether a state at time t is the next frame to keep after `kept` frames (on the grid k / rate, within round-off).
bool Due(double t, size_t kept, double rate = kViewFramesPerSecond) {
  return t >= (static_cast<double>(kept) - 1e-9) / rate;
}

}  // namespace

void CheckViewSize(const Model<double>& model, double frames, size_t series, const std::string& source) {
  const double numbers = frames * (7.0 * static_cast<double>(model.bodies.size()) + static_cast<double>(series));
  if (numbers > kMostViewNumbers) {
    throw InputError(source + ": the page would hold " + std::to_string(static_cast<long long>(frames)) +
                     " frames of " + std::to_string(model.bodies.size()) + " bodies, more than a browser opens (" +
                     std::to_string(static_cast<long long>(kMostViewNumbers)) +
                     " numbers at most): view a shorter run (--duration)");
  }
}

bool PlottedColumn(const TrajectoryColumn& column) {
  using Kind = TrajectoryColumn::Kind;
  return column.kind == Kind::kJointCoordinate || column.kind == Kind::kMarker ||
         column.kind == Kind::kConstraintError || column.kind == Kind::kEnergy;
}

ViewFrames SampledFrames(const std::string& source, const Model<double>& model, const std::vector<double>& times,
                         const std::function<VecX<double>(size_t)>& q_of_row,
                         const std::vector<std::string>& series_names,
                         const std::function<std::vector<double>(size_t)>& series_of_row, double frames_per_second) {
  ViewFrames frames;
  frames.series_names = series_names;
  size_t kept = 0;  // the frames to keep, counted first: a page too large is refused before it is made
  for (size_t row = 0; row < times.size(); ++row) {
    kept += row + 1 == times.size() || Due(times[row], kept, frames_per_second);
  }
  CheckViewSize(model, static_cast<double>(kept), series_names.size(), source);
  for (size_t row = 0; row < times.size(); ++row) {
    if (row + 1 < times.size() && !Due(times[row], frames.times.size(), frames_per_second)) continue;
    frames.times.push_back(times[row]);
    frames.poses.push_back(Poses(model, q_of_row(row)));
    frames.series.push_back(series_of_row(row));
  }
  return frames;
}

ViewFrames SimulatedFrames(const Model<double>& model) {
  ViewFrames frames;
  std::vector<TrajectoryColumn> plotted;
  for (const TrajectoryColumn& column : TrajectoryColumns(model)) {
    if (!PlottedColumn(column)) continue;
    plotted.push_back(column);
    frames.series_names.push_back(column.name);
  }
  CheckViewSize(model, std::ceil(model.simulation.duration * kViewFramesPerSecond) + 2, plotted.size(),
                "the scene's duration");
  double last_t = 0.0;  // the last state's
  std::vector<double> last_pose, last_series;
  const RunReport report = Simulate<double>(model, RunOptions{}, [&](const Sample<double>& s) {
    last_t = s.t;
    last_pose = Poses(model, s.q);
    last_series.clear();
    for (const TrajectoryColumn& column : plotted) last_series.push_back(ColumnValue(model, column, s));
    if (Due(s.t, frames.times.size())) {
      frames.times.push_back(s.t);
      frames.poses.push_back(last_pose);
      frames.series.push_back(last_series);
    }
  });
  if (frames.times.back() != last_t) {  // the last state, always
    frames.times.push_back(last_t);
    frames.poses.push_back(last_pose);
    frames.series.push_back(last_series);
  }
  for (const RunEvent& e : report.events) {
    frames.events.push_back({e.t, e.kind, e.constraint, e.point, e.normal, e.impulse});
  }
  frames.warnings = report.warnings;
  return frames;
}

ViewFrames RecordedFrames(const Model<double>& model, const std::string& csv_path) {
  return ObservedFrames(model, ReadTrajectory(csv_path, model), true);
}

ViewFrames ObservedFrames(const Model<double>& model, const Observations& data, bool poses_required) {
  const std::string& csv_path = data.path;
  std::map<int, int> column_of;  // q index -> column
  for (size_t c = 0; c < data.columns.size(); ++c) {
    if (data.columns[c].kind == TrajectoryColumn::Kind::kConfiguration) column_of[data.columns[c].index] = c;
  }
  bool posed = true;
  for (const Body<double>& body : model.bodies) {
    for (int k = 0; k < body.q_size; ++k) {
      if (column_of.count(body.q_offset + k)) continue;
      if (!poses_required) {
        posed = false;
        continue;
      }
      throw InputError(csv_path + ": no column for body '" + body.name +
                       "''s position or orientation: the view draws every body from its pose (the columns of "
                       "tether simulate's CSV: " +
                       body.name + ".x, ...)");
    }
  }
  if (!posed) column_of.clear();  // the series alone
  std::vector<int> plotted;  // the columns besides the poses
  std::vector<std::string> names;
  for (size_t c = 0; c < data.columns.size(); ++c) {
    if (data.columns[c].kind == TrajectoryColumn::Kind::kConfiguration) continue;
    plotted.push_back(static_cast<int>(c));
    names.push_back(data.columns[c].name);
  }
  const auto q_of_row = [&](size_t row) {
    VecX<double> q = VecX<double>::Zero(model.NumCoordinates());
    for (const auto& [index, column] : column_of) {
      q[index] = data.values[row][column];
      if (std::isnan(q[index])) {
        throw InputError(csv_path + ": line " + std::to_string(data.lines[row]) + ": the cell of column " +
                         data.columns[column].name + " is empty, and the view draws every pose it shows");
      }
    }
    return q;
  };
  const auto series_of_row = [&](size_t row) {
    std::vector<double> values;
    for (int c : plotted) values.push_back(data.values[row][c]);
    return values;
  };
  ViewFrames frames = SampledFrames(csv_path, model, data.times, q_of_row, names, series_of_row);
  if (!posed) frames.poses.clear();
  return frames;
}

}  // namespace tether
