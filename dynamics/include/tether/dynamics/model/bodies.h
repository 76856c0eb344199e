// The bodies of a model and the points fixed in them: what every part of a Model<T> (model.h) refers to.
#pragma once

#include <string>

#include "tether/dynamics/scalars/scalar.h"

namespace tether {

enum class BodyKind { kParticle, kPlanar, kRigid3d };

// Body index of the fixed ground frame.
inline constexpr int kWorld = -1;

// A body and its initial state as the scene gives it (world-frame angular velocity, the quaternion as written);
// InitialState (configuration_space.h) turns it into (q, v) at the start of a run.
template <typename T>
struct Body {
  std::string name;
  BodyKind kind = BodyKind::kParticle;
  T mass = T(1.0);                                         // kg, > 0
  T inertia = T(0.0);                                      // planar: kg m^2 about the centre of mass
  Mat3<T> inertia_tensor = Mat3<T>::Zero();                // 3D: kg m^2 about the centre of mass, body axes, symmetric
  Vec4<double> principal_axes = Vec4<double>(1, 0, 0, 0);  // 3D: R_BP, fixed at load (identity when the
                                                           // scene gives principal moments)
  Vec3<T> position = Vec3<T>::Zero();                      // m, world (components beyond the dimension are zero)
  T angle = T(0.0);                                        // planar: rad
  Vec4<T> orientation = Vec4<T>(T(1.0), T(0.0), T(0.0), T(0.0));  // 3D: q_WB, normalised at the start of a run
  Vec3<T> velocity = Vec3<T>::Zero();                             // m/s
  Vec3<T> angular_velocity = Vec3<T>::Zero();                     // rad/s, world frame (planar: z only)
  // where the body's numbers sit in q and in v
  int q_offset = 0, q_size = 0;
  int v_offset = 0, v_size = 0;
};

// A point fixed in a body, in body axes from the centre of mass (world coordinates when body == kWorld).
// Components beyond the scene's dimension are zero.
template <typename T>
struct BodyPoint {
  int body = kWorld;
  Vec3<T> local = Vec3<T>::Zero();

  template <typename U>
  BodyPoint<U> Cast() const {
    return {body, local.template cast<U>()};
  }
};

}  // namespace tether
