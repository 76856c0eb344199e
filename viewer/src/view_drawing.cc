#include <algorithm>
#include <cmath>

#include "tether/dynamics/constraints/joint_kinds.h"
#include "tether/dynamics/integration/simulator.h"
#include "tether/dynamics/model/rotation.h"
#include "tether/viewer/view.h"

namespace tether {
namespace {

using nlohmann::json;

json Vector(const Vec3<double>& x) { return {x[0], x[1], x[2]}; }
json Quaternion(const Vec4<double>& q) { return {q[0], q[1], q[2], q[3]}; }

// A planar angle as the quaternion of the turn about z.
Vec4<double> AboutZ(double angle) { return {std::cos(angle / 2), 0.0, 0.0, std::sin(angle / 2)}; }

json PointOf(const BodyPoint<double>& p) { return {{"body", p.body}, {"point", Vector(p.local)}}; }

// The glyph of a body without shapes (view.h): a uniform sphere, box or plate of its mass and inertia.
json Glyph(const Body<double>& body, double scale) {
  if (body.kind == BodyKind::kParticle) return {{"type", "sphere"}, {"radius", scale / 20}};
  const double m = body.mass, least = scale / 100;
  if (body.kind == BodyKind::kPlanar) {
    const double side = std::max(std::sqrt(6.0 * body.inertia / m), least);
    return {{"type", "box"}, {"size", {side, side, side / 5}}, {"rotation", {1.0, 0.0, 0.0, 0.0}}};
  }
  const Mat3<double> R_BP = RotationMatrix(body.principal_axes);
  const Vec3<double> moments = (R_BP.transpose() * body.inertia_tensor * R_BP).diagonal();
  const double sum = moments.sum();
  json size = json::array();
  for (int k = 0; k < 3; ++k)
    size.push_back(std::max(std::sqrt(std::max(6.0 * (sum - 2 * moments[k]) / m, 0.0)), least));
  return {{"type", "box"}, {"size", size}, {"rotation", Quaternion(body.principal_axes)}};
}

json ShapeOf(const Model<double>& model, const Shape<double>& shape, double scale) {
  json s = {{"name", shape.label},
            {"body", shape.body},
            {"type", ShapeTypeName(shape.type)},
            {"position", Vector(shape.position)},
            {"contact", shape.contact}};
  s["rotation"] = model.dimension == 3 ? Quaternion(shape.orientation.normalized()) : Quaternion(AboutZ(shape.angle));
  if (shape.type == ShapeType::kSphere || shape.type == ShapeType::kCapsule) s["radius"] = shape.radius;
  if (shape.type == ShapeType::kCapsule) s["length"] = shape.length;
  if (shape.type == ShapeType::kBox) {
    s["size"] = Vector(Vec3<double>(shape.size[0], shape.size[1], model.dimension == 3 ? shape.size[2] : scale / 20));
  }
  return s;
}

}  // namespace

json ViewDrawing(const Model<double>& model) {
  const double scale = LengthScale(model);
  json drawing = {{"dimension", model.dimension}, {"scale", scale}};
  json bodies = json::array();
  for (size_t b = 0; b < model.bodies.size(); ++b) {
    const Body<double>& body = model.bodies[b];
    const bool shaped = std::any_of(model.shapes.begin(), model.shapes.end(),
                                    [&](const Shape<double>& s) { return s.body == static_cast<int>(b); });
    json entry = {{"name", body.name}};
    if (!shaped) entry["glyph"] = Glyph(body, scale);
    bodies.push_back(entry);
  }
  drawing["bodies"] = bodies;
  double largest = scale;  // the view's scale: the scene's length scale, or a larger body (a cardan at the origin)
  for (const json& body : bodies) {
    if (body.contains("glyph") && body["glyph"].contains("size")) {
      for (const json& edge : body["glyph"]["size"]) largest = std::max(largest, edge.get<double>());
    }
  }
  json shapes = json::array();
  for (const Shape<double>& shape : model.shapes) shapes.push_back(ShapeOf(model, shape, scale));
  drawing["shapes"] = shapes;
  json joints = json::array();
  for (const Joint<double>& joint : model.joints) {
    json j = {
        {"name", joint.name}, {"type", JointTypeName(joint.type)}, {"a", PointOf(joint.a)}, {"b", PointOf(joint.b)}};
    const bool axial = joint.type == JointType::kHinge || joint.type == JointType::kSlider ||
                       joint.type == JointType::kPrismatic || joint.type == JointType::kCylindrical ||
                       joint.type == JointType::kUniversal || joint.type == JointType::kDoubleHinge;
    if (axial && model.dimension == 3) j["axis"] = Vector(joint.axis.normalized());
    joints.push_back(j);
  }
  drawing["joints"] = joints;
  json markers = json::array();
  for (const Marker<double>& marker : model.markers) {
    json m = PointOf(marker.point);
    m["name"] = marker.name;
    markers.push_back(m);
  }
  drawing["markers"] = markers;
  for (const Shape<double>& shape : model.shapes) {
    if (shape.type == ShapeType::kPlane) continue;
    largest = std::max({largest, 2 * shape.radius + shape.length, shape.size.maxCoeff()});
  }
  drawing["scale"] = largest;
  return drawing;
}

}  // namespace tether
