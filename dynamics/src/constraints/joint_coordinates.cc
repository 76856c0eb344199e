#include "tether/dynamics/constraints/joint_coordinates.h"

#include <cmath>

#include "tether/dynamics/constraints/constraint_rows.h"

namespace tether {
namespace {

template <typename T>
Mat3<T> RotationOf(const Model<T>& model, const BodyFrames<T>& frames, int body) {
  if (body == kWorld || model.bodies[body].kind == BodyKind::kParticle) return Mat3<T>::Identity();
  return frames[body].R_WB;
}

template <typename T>
Vec3<T> AngularVelocityOf(const Model<T>& model, const BodyFrames<T>& frames, int body) {
  if (body == kWorld || model.bodies[body].kind == BodyKind::kParticle) return Vec3<T>::Zero();
  return frames[body].w_W;
}

template <typename T>
T PlanarAngle(const Model<T>& model, int body, const VecX<T>& q) {
  return body == kWorld ? T(0.0) : q[model.bodies[body].q_offset + 2];
}

}  // namespace

template <typename T>
int JointCoordinates<T>::Find(int joint, JointCoordinate coordinate) const {
  for (size_t k = 0; k < references.size(); ++k) {
    if (references[k].joint == joint && references[k].coordinate == coordinate) return static_cast<int>(k);
  }
  return -1;
}

template <typename T>
int CoordinateIndex(const Model<T>& model, int joint, JointCoordinate coordinate) {
  int index = 0;
  for (int j = 0; j < static_cast<int>(model.joints.size()); ++j) {
    if (!TracksCoordinates(model.joints[j])) continue;
    for (JointCoordinate c : {JointCoordinate::kAngle, JointCoordinate::kDisplacement}) {
      if (!HasCoordinate(model, model.joints[j], c)) continue;
      if (j == joint && c == coordinate) return index;
      ++index;
    }
  }
  return -1;
}

template <typename T>
JointCoordinates<T> BuildJointCoordinates(const Model<T>& model, const VecX<T>& q) {
  using std::sqrt;
  JointCoordinates<T> out;
  BodyFrames<T> frames;
  UpdateFrames(model, q, q, false, &frames);
  for (size_t j = 0; j < model.joints.size(); ++j) {
    const Joint<T>& joint = model.joints[j];
    if (!TracksCoordinates(joint)) continue;
    for (JointCoordinate coordinate : {JointCoordinate::kAngle, JointCoordinate::kDisplacement}) {
      if (!HasCoordinate(model, joint, coordinate)) continue;
      CoordinateReference<T> r;
      r.joint = static_cast<int>(j);
      r.coordinate = coordinate;
      r.axis = joint.axis / sqrt(joint.axis.squaredNorm());
      if (coordinate == JointCoordinate::kAngle && model.dimension == 2) {
        r.offset = joint.angle - (PlanarAngle(model, joint.b.body, q) - PlanarAngle(model, joint.a.body, q));
      } else if (coordinate == JointCoordinate::kAngle) {
        Vec3<T> unused;
        AxisNormals(3, r.axis, &r.normal_a, &unused);
        const Mat3<T> R_BA =
            RotationOf(model, frames, joint.b.body).transpose() * RotationOf(model, frames, joint.a.body);
        r.normal_b = R_BA * r.normal_a;
        r.offset = joint.angle;
      }
      out.references.push_back(r);
      out.last.push_back(Value(r.offset));  // a 3D hinge's angle is theta_0 at the start: its branch
    }
  }
  for (size_t k = 0; k < out.references.size(); ++k) {
    out.last[k] = Value(EvaluateCoordinate(model, out, static_cast<int>(k), frames, q, q, false).value);
  }
  return out;
}

template <typename T>
CoordinateRow<T> EvaluateCoordinate(const Model<T>& model, const JointCoordinates<T>& coordinates, int k,
                                    const BodyFrames<T>& frames, const VecX<T>& q, const VecX<T>& v, bool velocities,
                                    bool value) {
  return EvaluateCoordinateAt(model, coordinates.references[k], coordinates.last[k], frames, q, v, velocities, value);
}

template <typename T>
CoordinateRow<T> EvaluateCoordinateAt(const Model<T>& model, const CoordinateReference<T>& r, double branch,
                                      const BodyFrames<T>& frames, const VecX<T>& q, const VecX<T>& v, bool velocities,
                                      bool value) {
  using std::atan2;
  const Joint<T>& joint = model.joints[r.joint];
  const int a = joint.a.body, b = joint.b.body;
  CoordinateRow<T> row;
  const Vec3<T> w_A = velocities ? AngularVelocityOf(model, frames, a) : Vec3<T>(Vec3<T>::Zero());
  if (r.coordinate == JointCoordinate::kAngle && model.dimension == 2) {
    row.value = r.offset + PlanarAngle(model, b, q) - PlanarAngle(model, a, q);
    if (velocities) row.rate = AngularVelocityOf(model, frames, b).z() - w_A.z();
    row.a.body = a;
    row.b.body = b;
    row.a.rotation.z() = T(-1.0);
    row.b.rotation.z() = T(1.0);
    return row;
  }
  const Mat3<T> R_WA = RotationOf(model, frames, a);
  const Vec3<T> axis_W = R_WA * r.axis;
  if (r.coordinate == JointCoordinate::kAngle) {
    if (value) {
      const Vec3<T> n_a = R_WA * r.normal_a;
      const Vec3<T> n_b = RotationOf(model, frames, b) * r.normal_b;
      const T raw = r.offset + atan2(n_a.cross(n_b).dot(axis_W), n_a.dot(n_b));
      const double turns = std::round((branch - Value(raw)) / (2.0 * M_PI));
      row.value = raw + T(2.0 * M_PI * turns);
    }
    if (velocities) row.rate = (AngularVelocityOf(model, frames, b) - w_A).dot(axis_W);
    row.a.body = a;
    row.b.body = b;
    row.a.rotation = RotationalPart(model, frames, a, Vec3<T>(-axis_W));
    row.b.rotation = RotationalPart(model, frames, b, axis_W);
    return row;
  }
  const PointMotion<T> pa = MovePoint(model, frames, joint.a, q, v, velocities);
  const PointMotion<T> pb = MovePoint(model, frames, joint.b, q, v, velocities);
  const Vec3<T> d = pb.position - pa.position;
  row.value = axis_W.dot(d);
  if (velocities) row.rate = axis_W.dot(pb.velocity - pa.velocity) + w_A.dot(axis_W.cross(d));
  row.a = PointGradient(model, frames, a, Vec3<T>(-axis_W), pa);
  row.a.rotation += RotationalPart(model, frames, a, Vec3<T>(axis_W.cross(d)));
  row.b = PointGradient(model, frames, b, axis_W, pb);
  return row;
}

template <typename T>
T CoordinateBias(const Model<T>& model, const CoordinateReference<T>& r, const BodyFrames<T>& frames, const VecX<T>& q,
                 const VecX<T>& v) {
  const Joint<T>& joint = model.joints[r.joint];
  if (r.coordinate == JointCoordinate::kAngle && model.dimension == 2) return T(0.0);
  const Vec3<T> w_A = AngularVelocityOf(model, frames, joint.a.body);
  const Vec3<T> axis_W = RotationOf(model, frames, joint.a.body) * r.axis;
  const Vec3<T> turn = w_A.cross(axis_W);
  if (r.coordinate == JointCoordinate::kAngle) return (AngularVelocityOf(model, frames, joint.b.body) - w_A).dot(turn);
  const PointMotion<T> pa = MovePoint(model, frames, joint.a, q, v, true);
  const PointMotion<T> pb = MovePoint(model, frames, joint.b, q, v, true);
  return axis_W.dot(pb.centripetal - pa.centripetal) + T(2.0) * turn.dot(Vec3<T>(pb.velocity - pa.velocity)) +
         w_A.cross(turn).dot(Vec3<T>(pb.position - pa.position));
}

template <typename T>
void TrackCoordinates(const Model<T>& model, const BodyFrames<T>& frames, const VecX<T>& q, const VecX<T>& v,
                      JointCoordinates<T>* coordinates) {
  for (size_t k = 0; k < coordinates->references.size(); ++k) {
    coordinates->last[k] =
        Value(EvaluateCoordinate(model, *coordinates, static_cast<int>(k), frames, q, v, false).value);
  }
}

#define TETHER_INSTANTIATE_JOINT_COORDINATES(T)                                                                        \
  template struct JointCoordinates<T>;                                                                                 \
  template int CoordinateIndex<T>(const Model<T>&, int, JointCoordinate);                                              \
  template JointCoordinates<T> BuildJointCoordinates<T>(const Model<T>&, const VecX<T>&);                              \
  template CoordinateRow<T> EvaluateCoordinate<T>(const Model<T>&, const JointCoordinates<T>&, int,                    \
                                                  const BodyFrames<T>&, const VecX<T>&, const VecX<T>&, bool, bool);   \
  template CoordinateRow<T> EvaluateCoordinateAt<T>(const Model<T>&, const CoordinateReference<T>&, double,            \
                                                    const BodyFrames<T>&, const VecX<T>&, const VecX<T>&, bool, bool); \
  template T CoordinateBias<T>(const Model<T>&, const CoordinateReference<T>&, const BodyFrames<T>&, const VecX<T>&,   \
                               const VecX<T>&);                                                                        \
  template void TrackCoordinates<T>(const Model<T>&, const BodyFrames<T>&, const VecX<T>&, const VecX<T>&,             \
                                    JointCoordinates<T>*);
TETHER_FOR_EACH_SCALAR(TETHER_INSTANTIATE_JOINT_COORDINATES)

}  // namespace tether
