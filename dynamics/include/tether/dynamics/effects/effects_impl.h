// Definitions for effects.h; included only by the file that instantiates them.
#pragma once

#include <cmath>

#include "tether/dynamics/adjoint/recorded.h"
#include "tether/dynamics/effects/effect_context.h"
#include "tether/dynamics/effects/effects.h"

namespace tether {

template <typename T>
Mat3<T> PrincipalInertia(const Mat3<T>& inertia_tensor, const Vec4<double>& principal_axes) {
  Mat3<T> symmetric = inertia_tensor;  // the upper triangle holds the products of inertia
  symmetric(1, 0) = symmetric(0, 1);
  symmetric(2, 0) = symmetric(0, 2);
  symmetric(2, 1) = symmetric(1, 2);
  if (principal_axes == Vec4<double>(1, 0, 0, 0)) return symmetric;
  const Mat3<T> R_BP = RotationMatrix(Vec4<T>(principal_axes.template cast<T>()));
  return R_BP.transpose() * symmetric * R_BP;
}

template <typename T>
std::vector<Mat3<T>> PrincipalInertias(const Model<T>& model) {
  std::vector<Mat3<T>> inertias(model.bodies.size(), Mat3<T>::Zero());
  for (int index : model.spatial_bodies) inertias[index] = PrincipalInertia(model.bodies[index]);
  return inertias;
}

template <typename T>
TETHER_FLATTEN void AccumulateForces(const Model<T>& model, const JointCoordinates<T>& coordinates,
                                     const std::vector<Mat3<T>>& principal_inertia, const BodyFrames<T>& frames,
                                     double t, const VecX<T>& q, const VecX<T>& v, VecX<T>* f) {
  const EffectContext<T> context{model, coordinates, frames, t, q, v};
  ForEachEffectList(
      [&context, f](const auto& list) {
        for (const auto& effect : list) effect.AddForces(context, f);
      },
      model);
  if (RecordedGyroscopicTorques(model, v, f)) return;
  for (int index : model.spatial_bodies) {
    const Body<T>& body = model.bodies[index];
    const Vec3<T> w_P = v.template segment<3>(body.v_offset + 3);
    f->template segment<3>(body.v_offset + 3) -= w_P.cross(Vec3<T>(principal_inertia[index] * w_P));
  }
}

template <typename T>
T KineticEnergy(const Model<T>& model, const VecX<T>& v) {
  T energy(0.0);
  for (const Body<T>& body : model.bodies) {
    const Vec3<T> velocity = Translation(model.dimension, v.data() + body.v_offset);
    energy += T(0.5) * body.mass * velocity.squaredNorm();
    if (body.kind == BodyKind::kPlanar) energy += T(0.5) * body.inertia * v[body.v_offset + 2] * v[body.v_offset + 2];
    if (body.kind == BodyKind::kRigid3d) {
      const Vec3<T> w_P = v.template segment<3>(body.v_offset + 3);
      energy += T(0.5) * w_P.dot(PrincipalInertia(body) * w_P);
    }
  }
  return energy;
}

template <typename T>
T Energy(const Model<T>& model, const JointCoordinates<T>& coordinates, const BodyFrames<T>& frames, const VecX<T>& q,
         const VecX<T>& v) {
  T energy = KineticEnergy(model, v);
  const EffectContext<T> context{model, coordinates, frames, 0.0, q, v};  // no potential depends on time
  ForEachEffectList(
      [&context, &energy](const auto& list) {
        for (const auto& effect : list) energy += effect.Energy(context);
      },
      model);
  return energy;
}

}  // namespace tether
