// The columns of the trajectory CSV (docs/contract.md), each a function of a sample, for output, data and targets:
//   t; per body in scene order: NAME.x, NAME.y[, NAME.z], then NAME.angle (planar rigid) or NAME.qw .. NAME.qz
//   (3D rigid), then NAME.vx, NAME.vy[, NAME.vz], then NAME.omega (planar) or NAME.wx .. NAME.wz (3D, world
//   frame); per named joint with coordinates, in scene order: NAME.angle, NAME.omega and/or NAME.displacement,
//   NAME.speed; per marker: NAME.x, NAME.y[, NAME.z]; then constraint_error and energy.
#pragma once

#include <string>
#include <vector>

#include "tether/dynamics/integration/simulator.h"

namespace tether {

struct TrajectoryColumn {
  enum class Kind {
    kTime,
    kConfiguration,         // q[index]
    kVelocity,              // v[index]
    kWorldAngularVelocity,  // body `index`, world component `component`
    kJointCoordinate,       // Sample::coordinates[index]
    kJointRate,             // Sample::coordinate_rates[index]
    kMarker,                // marker `index`, world component `component`
    kConstraintError,
    kEnergy
  };
  std::string name;
  Kind kind = Kind::kTime;
  int index = 0;
  int component = 0;
  int body = kWorld;  // the body whose orientation a quaternion column (qw .. qz) belongs to, else kWorld
};

std::vector<TrajectoryColumn> TrajectoryColumns(const Model<double>& model);

// The column's value at a sample of a run of `model`.
template <typename T>
T ColumnValue(const Model<T>& model, const TrajectoryColumn& column, const Sample<T>& sample);

}  // namespace tether
