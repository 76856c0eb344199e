#include "tether/dynamics/io/trajectory_columns.h"

#include "tether/dynamics/constraints/joint_coordinates.h"

namespace tether {

std::vector<TrajectoryColumn> TrajectoryColumns(const Model<double>& model) {
  using Kind = TrajectoryColumn::Kind;
  static const char* kAxes[3] = {"x", "y", "z"};
  static const char* kQuaternion[4] = {"qw", "qx", "qy", "qz"};
  const int d = model.dimension;
  std::vector<TrajectoryColumn> columns = {{"t", Kind::kTime}};
  for (size_t i = 0; i < model.bodies.size(); ++i) {
    const Body<double>& body = model.bodies[i];
    const std::string& n = body.name;
    for (int k = 0; k < d; ++k) columns.push_back({n + "." + kAxes[k], Kind::kConfiguration, body.q_offset + k});
    if (body.kind == BodyKind::kPlanar) columns.push_back({n + ".angle", Kind::kConfiguration, body.q_offset + 2});
    if (body.kind == BodyKind::kRigid3d) {
      for (int k = 0; k < 4; ++k) {
        columns.push_back(
            {n + "." + kQuaternion[k], Kind::kConfiguration, body.q_offset + 3 + k, k, static_cast<int>(i)});
      }
    }
    for (int k = 0; k < d; ++k) columns.push_back({n + ".v" + kAxes[k], Kind::kVelocity, body.v_offset + k});
    if (body.kind == BodyKind::kPlanar) columns.push_back({n + ".omega", Kind::kVelocity, body.v_offset + 2});
    if (body.kind == BodyKind::kRigid3d) {
      for (int k = 0; k < 3; ++k) {
        columns.push_back({n + ".w" + kAxes[k], Kind::kWorldAngularVelocity, static_cast<int>(i), k});
      }
    }
  }
  for (int j = 0; j < static_cast<int>(model.joints.size()); ++j) {  // named joints' coordinates, in scene order
    const Joint<double>& joint = model.joints[j];
    if (joint.name.empty()) continue;
    if (HasCoordinate(model, joint, JointCoordinate::kAngle)) {
      const int reference = CoordinateIndex(model, j, JointCoordinate::kAngle);
      columns.push_back({joint.name + ".angle", Kind::kJointCoordinate, reference});
      columns.push_back({joint.name + ".omega", Kind::kJointRate, reference});
    }
    if (HasCoordinate(model, joint, JointCoordinate::kDisplacement)) {
      const int reference = CoordinateIndex(model, j, JointCoordinate::kDisplacement);
      columns.push_back({joint.name + ".displacement", Kind::kJointCoordinate, reference});
      columns.push_back({joint.name + ".speed", Kind::kJointRate, reference});
    }
  }
  for (size_t m = 0; m < model.markers.size(); ++m) {
    for (int k = 0; k < d; ++k) {
      columns.push_back({model.markers[m].name + "." + kAxes[k], Kind::kMarker, static_cast<int>(m), k});
    }
  }
  columns.push_back({"constraint_error", Kind::kConstraintError});
  columns.push_back({"energy", Kind::kEnergy});
  return columns;
}

template <typename T>
T ColumnValue(const Model<T>& model, const TrajectoryColumn& column, const Sample<T>& s) {
  using Kind = TrajectoryColumn::Kind;
  switch (column.kind) {
    case Kind::kTime:
      return T(s.t);
    case Kind::kConfiguration:
      return s.q[column.index];
    case Kind::kVelocity:
      return s.v[column.index];
    case Kind::kWorldAngularVelocity:
      return s.frames[column.index].w_W[column.component];
    case Kind::kJointCoordinate:
      return s.coordinates[column.index];
    case Kind::kJointRate:
      return s.coordinate_rates[column.index];
    case Kind::kMarker:
      return MovePoint(model, s.frames, model.markers[column.index].point, s.q, s.v, false).position[column.component];
    case Kind::kConstraintError:
      return T(s.constraint_error);
    case Kind::kEnergy:
      return s.energy;
  }
  return T(0.0);
}

template double ColumnValue<double>(const Model<double>&, const TrajectoryColumn&, const Sample<double>&);
template Jet ColumnValue<Jet>(const Model<Jet>&, const TrajectoryColumn&, const Sample<Jet>&);
template Rev ColumnValue<Rev>(const Model<Rev>&, const TrajectoryColumn&, const Sample<Rev>&);

}  // namespace tether
