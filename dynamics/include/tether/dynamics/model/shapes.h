// Contact shapes (docs/contract.md, "Joint limits, contact and impacts"; docs/contact.md): solid primitives fixed in
// a body (or the world), each in its own frame S placed in the body frame B by a position p_BS and a rotation
// R_BS (a unit quaternion in 3D, an angle about z in 2D):
//   sphere   |x_S| <= radius (a disc in 2D)
//   capsule  the points within `radius` of the segment from (-length/2, 0, 0) to (length/2, 0, 0)
//   box      |x_S,k| <= size_k / 2 on every axis k of the dimension
//   plane    x_S . n <= 0, n = z in 3D and y in 2D (the outward normal through the origin: everything below is
//            solid)
// The contact law of a pair of shapes takes the larger of their frictions and of their restitutions (MuJoCo's
// rule); a shape that gives neither takes the scene's defaults (ContactSettings).
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "tether/dynamics/model/bodies.h"
#include "tether/dynamics/model/rotation.h"

namespace tether {

enum class ShapeType { kSphere, kCapsule, kBox, kPlane };

// The scene format's name of a type.
const char* ShapeTypeName(ShapeType type);

template <typename T>
struct Shape {
  int scene_index = 0;  // position in the scene's "shapes"
  std::string label;    // its name, else BODY#INDEX (INDEX its position among its body's shapes)
  int body = kWorld;
  ShapeType type = ShapeType::kSphere;
  Vec3<T> position = Vec3<T>::Zero();                             // p_BS, m, body frame
  Vec4<T> orientation = Vec4<T>(T(1.0), T(0.0), T(0.0), T(0.0));  // 3D: q_BS, normalised where it is used
  T angle = T(0.0);                                               // 2D: rad
  T radius = T(0.0);                                              // sphere, capsule: m, > 0
  T length = T(0.0);                                              // capsule: between the cap centres, m, >= 0
  Vec3<T> size = Vec3<T>::Zero();                                 // box: full edge lengths, m, > 0
  T friction = T(0.0), restitution = T(0.0);  // used where the shape gives them (gives_*), else the defaults
  bool gives_friction = false, gives_restitution = false;
  bool contact = true;  // false: drawn, never touched

  template <typename U>
  Shape<U> Cast() const {
    return {scene_index,
            label,
            body,
            type,
            position.template cast<U>(),
            orientation.template cast<U>(),
            U(angle),
            U(radius),
            U(length),
            size.template cast<U>(),
            U(friction),
            U(restitution),
            gives_friction,
            gives_restitution,
            contact};
  }
};

enum class ContactMode { kEvents, kStepping };

// The scene's "contact": the law's defaults and the body pairs that never touch.
template <typename T>
struct ContactSettings {
  T friction = T(0.0), restitution = T(0.0);
  std::vector<std::pair<int, int>> exclude;  // body indices (kWorld for the world), either order

  template <typename U>
  ContactSettings<U> Cast() const {
    return {U(friction), U(restitution), exclude};
  }
};

// R_BS of a shape in a scene of `dimension`.
template <typename T>
Mat3<T> ShapeRotation(const Shape<T>& shape, int dimension) {
  if (dimension == 3) {
    using std::sqrt;
    return RotationMatrix(Vec4<T>(shape.orientation / sqrt(shape.orientation.squaredNorm())));
  }
  return PlanarRotation(shape.angle);
}

}  // namespace tether
