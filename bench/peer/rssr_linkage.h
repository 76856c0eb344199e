// scenes/rssr.json's spatial four-bar (scenes/make_3d_scenes.py, rssr()), described once for the peers: a crank of
// 1 m hinged to the world at the origin about z, starting 60 degrees from +x; a rocker of 1.5 m hinged about x at
// (3, 0, 1), hanging straight down; a coupler from the crank's tip to the rocker's tip with ball joints at both ends
// (its spin about its own line is the linkage's second, idle, degree of freedom). Every bar is a 1 kg rod of radius
// 2 cm, at rest; gravity -9.81 z; a motor turns the crank with 2 N m about +z. tether reads the scene file itself
// (tether_models.h); MuJoCo and Simbody build the same linkage from these points, with every body's axes the
// world's at the start and its inertia written in them:
//   I = I_axial u u^T + I_across (1 - u u^T),   u the rod's unit direction, (I_axial, I_across) = RodInertia.
#pragma once

#include <cmath>

#include "bench_models.h"
#include "tether/dynamics/scalars/scalar.h"

namespace tether::bench {

struct Rssr {
  Vec3<double> crank_pivot, crank_tip, rocker_pivot, rocker_tip;  // world, at the start
  Vec3<double> crank_axis, rocker_axis;                           // the hinges' axes, world
  double drive_torque;                                            // N m on the crank about crank_axis
};

inline Rssr RssrLinkage() {
  const double start = M_PI / 3, rocker = 1.5;
  const Vec3<double> pivot(3.0, 0.0, 1.0);
  return {Vec3<double>::Zero(),
          Vec3<double>(std::cos(start), std::sin(start), 0.0),
          pivot,
          pivot - Vec3<double>(0.0, 0.0, rocker),
          Vec3<double>::UnitZ(),
          Vec3<double>::UnitX(),
          2.0};
}

// A 1 kg rod from a to b: its inertia about its centre, world axes, kg m^2.
inline Mat3<double> RodInertiaInWorld(const Vec3<double>& a, const Vec3<double>& b) {
  const Vec3<double> moments = RodInertia(1.0, (b - a).norm());
  const Vec3<double> u = (b - a).normalized();
  const Mat3<double> along = u * u.transpose();
  return moments.x() * along + moments.y() * (Mat3<double>::Identity() - along);
}

}  // namespace tether::bench
