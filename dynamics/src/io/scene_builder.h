// The scene reader's builder (scene_reader.cc), shared with its table of effects (effect_reader.cc): it validates a
// scene document key by key, builds its Model<double>, and binds every number it reads to the model field it lands
// in (scene_numbers.h). Every failure is an InputError naming the file and the JSON Pointer.
#pragma once

#include <Eigen/Eigenvalues>
#include <cmath>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "tether/dynamics/constraints/constraint_rows.h"
#include "tether/dynamics/io/names.h"
#include "tether/dynamics/io/scene_numbers.h"
#include "tether/dynamics/io/scene_reader.h"
#include "tether/dynamics/model/configuration_space.h"
#include "tether/dynamics/model/errors.h"
#include "tether/dynamics/model/kinematics.h"
#include "tether/dynamics/solvers/schur_system.h"

namespace tether::reading {

// How far outside its range a joint may start, in rad or m: rounding, not a position (a URDF prismatic joint at its
// lower stop started 1.7e-16 m below it and its import was refused).
constexpr double kRangeRounding = 1e-12;

using nlohmann::json;

inline const char* TypeName(const json& j) {
  if (j.is_boolean()) return "a boolean";
  if (j.is_number()) return "a number";
  if (j.is_string()) return "a string";
  if (j.is_array()) return "an array";
  if (j.is_object()) return "an object";
  return "null";
}

inline std::string Escape(const std::string& key) {  // RFC 6901
  std::string out;
  for (char c : key) {
    if (c == '~') {
      out += "~0";
    } else if (c == '/') {
      out += "~1";
    } else {
      out += c;
    }
  }
  return out;
}

inline std::string Child(const std::string& pointer, const std::string& key) { return pointer + "/" + Escape(key); }
inline std::string Child(const std::string& pointer, size_t index) { return pointer + "/" + std::to_string(index); }

inline std::string Format(double x) {
  std::ostringstream out;
  out << x;
  return out.str();
}

// Validating accessors; every failure names the file and the JSON Pointer.
class Validator {
 public:
  explicit Validator(std::string path) : path_(std::move(path)) {}

  // "FILE: POINTER", how every message starts.
  std::string Where(const std::string& pointer) const {
    return path_ + ": " + (pointer.empty() ? std::string("(top level)") : pointer);
  }

  [[noreturn]] void Fail(const std::string& pointer, const std::string& message) const {
    throw InputError(Where(pointer) + ": " + message);
  }

  void Object(const json& j, const std::string& pointer, const std::set<std::string>& allowed) const {
    if (!j.is_object()) Fail(pointer, std::string("expected an object, got ") + TypeName(j));
    for (auto it = j.begin(); it != j.end(); ++it) {
      if (!allowed.count(it.key())) {
        std::string list;
        for (const std::string& k : allowed) list += (list.empty() ? "" : ", ") + k;
        Fail(Child(pointer, it.key()), "unknown key '" + it.key() + "' (allowed here: " + list + ")");
      }
    }
  }

  const json& Required(const json& object, const std::string& pointer, const char* key) const {
    if (!object.contains(key)) Fail(pointer, std::string("missing required key '") + key + "'");
    return object.at(key);
  }

  const json* Optional(const json& object, const char* key) const {
    return object.contains(key) ? &object.at(key) : nullptr;
  }

  double Number(const json& j, const std::string& pointer) const {
    if (!j.is_number()) Fail(pointer, std::string("expected a number, got ") + TypeName(j));
    const double x = j.get<double>();
    if (!std::isfinite(x)) Fail(pointer, "must be finite");
    return x;
  }
  double Positive(const json& j, const std::string& pointer) const {
    const double x = Number(j, pointer);
    if (!(x > 0)) Fail(pointer, "must be > 0, got " + Format(x));
    return x;
  }
  double NonNegative(const json& j, const std::string& pointer) const {
    const double x = Number(j, pointer);
    if (!(x >= 0)) Fail(pointer, "must be >= 0, got " + Format(x));
    return x;
  }

  std::string String(const json& j, const std::string& pointer) const {
    if (!j.is_string()) Fail(pointer, std::string("expected a string, got ") + TypeName(j));
    return j.get<std::string>();
  }

  const json& Array(const json& j, const std::string& pointer) const {
    if (!j.is_array()) Fail(pointer, std::string("expected an array, got ") + TypeName(j));
    return j;
  }

  // An array of exactly `size` numbers, as a Vec3 padded with zeros.
  Vec3<double> Vector(const json& j, const std::string& pointer, int size) const {
    Array(j, pointer);
    if (static_cast<int>(j.size()) != size) {
      Fail(pointer,
           "expected " + std::to_string(size) + " numbers (the scene's dimension), got " + std::to_string(j.size()));
    }
    Vec3<double> v = Vec3<double>::Zero();
    for (int k = 0; k < size; ++k) v[k] = Number(j[k], Child(pointer, k));
    return v;
  }

 private:
  std::string path_;
};

class SceneBuilder {
 public:
  SceneBuilder(const json& document, const std::string& path) : doc_(document), check_(path) {}

  // The model, and the record of where each of its numbers came from.
  void Build(Model<double>* model, SceneNumbers* numbers) {
    check_.Object(doc_, "",
                  {"dimension", "bodies", "constraints", "contact", "effects", "markers", "shapes", "simulation",
                   "stabilization"});
    if (const json* d = check_.Optional(doc_, "dimension")) {
      const double dim = check_.Number(*d, "/dimension");
      if (dim != 2 && dim != 3) check_.Fail("/dimension", "must be 2 or 3, got " + Format(dim));
      model_.dimension = static_cast<int>(dim);
    }
    ReadBodies(check_.Required(doc_, "", "bodies"));
    if (const json* c = check_.Optional(doc_, "constraints")) ReadConstraints(*c);
    CheckRowsOnEachBody();
    if (const json* m = check_.Optional(doc_, "markers")) ReadMarkers(*m);
    if (const json* c = check_.Optional(doc_, "contact")) ReadContact(*c);
    if (const json* shapes = check_.Optional(doc_, "shapes")) ReadShapes(*shapes);
    if (const json* e = check_.Optional(doc_, "effects")) ReadEffects(*e);
    if (const json* s = check_.Optional(doc_, "simulation")) ReadSimulation(*s);
    if (const json* s = check_.Optional(doc_, "stabilization")) ReadStabilization(*s);
    *model = std::move(model_);
    *numbers = std::move(numbers_);
  }

  // The helpers below are the reading vocabulary the effect readers (effect_reader.cc) use too.
  const Validator& check() const { return check_; }
  Model<double>& model() { return model_; }
  int Dim() const { return model_.dimension; }

  // Records that the number at `pointer` lands in the model field `access` reaches, a generic lambda
  // [](auto& model) -> auto& { return ...; } (scene_numbers.h); `field` shares an earlier pointer's field.
  template <typename Access>
  int Bind(const std::string& pointer, NumberDomain domain, Access access, std::optional<ScheduleKnot> knot = {},
           int field = -1) {
    return numbers_.Add(pointer, domain, ModelField(access), std::move(knot), field);
  }
  // The same for the `size` numbers of a vector at `pointer`: number k lands in component k of access's vector.
  template <typename Access>
  void BindVector(const std::string& pointer, int size, NumberDomain domain, Access access,
                  std::optional<ScheduleKnot> knot = {}) {
    for (int k = 0; k < size; ++k) {
      if (knot) knot->component = k;
      Bind(
          Child(pointer, k), domain, [ access, k ](auto& m) -> auto& { return access(m)[k]; }, knot);
    }
  }
  // The two points of a two-body element at `at`/points, when it gives them.
  template <typename AccessA, typename AccessB>
  void BindPoints(const json& element, const std::string& at, AccessA a, AccessB b) {
    if (!element.contains("points")) return;
    BindVector(Child(Child(at, "points"), 0), Dim(), NumberDomain::kAny, a);
    BindVector(Child(Child(at, "points"), 1), Dim(), NumberDomain::kAny, b);
  }
  // Each value of the schedule at `at`/schedule: bind_value(its pointer, its index j, its knot).
  template <typename BindValue>
  void BindSchedule(const std::string& at, const std::vector<double>& times, BindValue bind_value) {
    const std::string schedule = Child(at, "schedule"), values = Child(schedule, "values");
    for (size_t j = 0; j < times.size(); ++j) {
      bind_value(Child(values, j), static_cast<int>(j), ScheduleKnot{schedule, static_cast<int>(j), 0, times});
    }
  }

  void ReadBodies(const json& bodies) {
    check_.Array(bodies, "/bodies");
    if (bodies.empty()) check_.Fail("/bodies", "a scene needs at least one body");
    for (size_t i = 0; i < bodies.size(); ++i) {
      const std::string at = Child("/bodies", i);
      const json& b = bodies[i];
      if (!b.is_object()) check_.Fail(at, std::string("expected an object, got ") + TypeName(b));
      const std::string type = check_.String(check_.Required(b, at, "type"), Child(at, "type"));
      BodyKind kind;
      if (type == "particle") {
        kind = BodyKind::kParticle;
        check_.Object(b, at, {"name", "type", "mass", "position", "velocity"});
      } else if (type == "rigid") {
        kind = Dim() == 2 ? BodyKind::kPlanar : BodyKind::kRigid3d;
        if (Dim() == 2) {
          check_.Object(b, at,
                        {"name", "type", "mass", "inertia", "position", "angle", "velocity", "angular_velocity"});
        } else {
          check_.Object(b, at,
                        {"name", "type", "mass", "inertia", "position", "orientation", "velocity", "angular_velocity"});
        }
      } else {
        check_.Fail(Child(at, "type"), "unknown body type '" + type + "' (expected particle or rigid)");
      }
      const std::string name = NewName(b, at, true);
      names_[name] = static_cast<int>(i);
      const double mass = check_.Positive(check_.Required(b, at, "mass"), Child(at, "mass"));
      const Vec3<double> position = check_.Vector(check_.Required(b, at, "position"), Child(at, "position"), Dim());
      Vec3<double> velocity = Vec3<double>::Zero();
      if (const json* v = check_.Optional(b, "velocity")) velocity = check_.Vector(*v, Child(at, "velocity"), Dim());
      if (kind == BodyKind::kRigid3d) {
        const Mat3<double> inertia = Inertia(check_.Required(b, at, "inertia"), Child(at, "inertia"));
        Vec4<double> orientation(1, 0, 0, 0);
        if (const json* o = check_.Optional(b, "orientation")) orientation = Orientation(*o, Child(at, "orientation"));
        Vec3<double> omega = Vec3<double>::Zero();
        if (const json* w = check_.Optional(b, "angular_velocity"))
          omega = check_.Vector(*w, Child(at, "angular_velocity"), 3);
        AddRigidBody3d(&model_, name, mass, inertia, position, orientation, velocity, omega);
        continue;
      }
      const double inertia =
          kind == BodyKind::kPlanar ? check_.Positive(check_.Required(b, at, "inertia"), Child(at, "inertia")) : 0.0;
      double angle = 0.0, omega = 0.0;
      if (const json* a = check_.Optional(b, "angle")) angle = check_.Number(*a, Child(at, "angle"));
      if (const json* w = check_.Optional(b, "angular_velocity"))
        omega = check_.Number(*w, Child(at, "angular_velocity"));
      AddBody(&model_, name, kind, mass, inertia, position, angle, velocity, omega);
    }
    for (size_t i = 0; i < bodies.size(); ++i) BindBody(bodies[i], Child("/bodies", i), static_cast<int>(i));
  }

  // The numbers of body i, as it gives them.
  void BindBody(const json& b, const std::string& at, int i) {
    using D = NumberDomain;
    const bool planar = model_.bodies[i].kind == BodyKind::kPlanar,
               spatial = model_.bodies[i].kind == BodyKind::kRigid3d;
    Bind(
        Child(at, "mass"), D::kPositive, [i](auto& m) -> auto& { return m.bodies[i].mass; });
    BindVector(
        Child(at, "position"), Dim(), D::kAny, [i](auto& m) -> auto& { return m.bodies[i].position; });
    if (b.contains("velocity")) {
      BindVector(
          Child(at, "velocity"), Dim(), D::kAny, [i](auto& m) -> auto& { return m.bodies[i].velocity; });
    }
    if (planar) {
      Bind(
          Child(at, "inertia"), D::kPositive, [i](auto& m) -> auto& { return m.bodies[i].inertia; });
      if (b.contains("angle"))
        Bind(
            Child(at, "angle"), D::kAny, [i](auto& m) -> auto& { return m.bodies[i].angle; });
      if (b.contains("angular_velocity")) {
        Bind(
            Child(at, "angular_velocity"), D::kAny, [i](auto& m) -> auto& { return m.bodies[i].angular_velocity[2]; });
      }
    }
    if (!spatial) return;
    const std::string inertia = Child(at, "inertia");
    const bool tensor = b.at("inertia")[0].is_array();
    for (int r = 0; r < 3; ++r) {  // a principal moment, or a tensor's row (a product's two places share its field)
      if (!tensor) {
        Bind(
            Child(inertia, r), D::kPositive, [ i, r ](auto& m) -> auto& { return m.bodies[i].inertia_tensor(r, r); });
        continue;
      }
      Bind(
          Child(Child(inertia, r), r), D::kPositive,
          [ i, r ](auto& m) -> auto& { return m.bodies[i].inertia_tensor(r, r); });
      for (int c = r + 1; c < 3; ++c) {
        const int field = Bind(
            Child(Child(inertia, r), c), D::kAny,
            [ i, r, c ](auto& m) -> auto& { return m.bodies[i].inertia_tensor(r, c); });
        Bind(
            Child(Child(inertia, c), r), D::kAny,
            [ i, r, c ](auto& m) -> auto& { return m.bodies[i].inertia_tensor(r, c); }, {}, field);
      }
    }
    if (b.contains("orientation")) {
      BindVector(
          Child(at, "orientation"), 4, D::kAny, [i](auto& m) -> auto& { return m.bodies[i].orientation; });
    }
    if (b.contains("angular_velocity")) {
      BindVector(
          Child(at, "angular_velocity"), 3, D::kAny, [i](auto& m) -> auto& { return m.bodies[i].angular_velocity; });
    }
  }

  // A name for a body, a constraint or a marker: not empty, not "world", unique among all three.
  std::string NewName(const json& element, const std::string& at, bool required) {
    const json* j = required ? &check_.Required(element, at, "name") : check_.Optional(element, "name");
    if (!j) return "";
    const std::string where = Child(at, "name");
    const std::string name = check_.String(*j, where);
    if (name.empty()) check_.Fail(where, "a name must not be empty");
    if (name == "world") check_.Fail(where, "the name 'world' is reserved for the fixed ground frame");
    auto seen = all_names_.find(name);
    if (seen != all_names_.end()) check_.Fail(where, "duplicate name '" + name + "' (also " + seen->second + ")");
    all_names_[name] = at;
    return name;
  }

  // A 3D body's inertia: three principal moments or a symmetric tensor (body axes, about the centre of mass),
  // positive definite, each principal moment at most the sum of the other two (to a relative 1e-12).
  Mat3<double> Inertia(const json& j, const std::string& at) const {
    check_.Array(j, at);
    Mat3<double> inertia = Mat3<double>::Zero();
    if (j.size() == 3 && j[0].is_array()) {
      for (int r = 0; r < 3; ++r) inertia.row(r) = check_.Vector(j[r], Child(at, r), 3).transpose();
      const double size = inertia.cwiseAbs().maxCoeff();
      for (int r = 0; r < 3; ++r) {
        for (int c = r + 1; c < 3; ++c) {
          if (std::abs(inertia(r, c) - inertia(c, r)) > 1e-12 * size) {
            check_.Fail(at, "the inertia tensor must be symmetric: entries " + std::to_string(r) + "," +
                                std::to_string(c) + " and " + std::to_string(c) + "," + std::to_string(r) +
                                " differ (" + Format(inertia(r, c)) + " and " + Format(inertia(c, r)) + ")");
          }
        }
      }
    } else if (j.size() == 3) {
      inertia = check_.Vector(j, at, 3).asDiagonal();
    } else {
      check_.Fail(at, "expected three principal moments [Ixx, Iyy, Izz] or a 3 x 3 tensor, got " +
                          std::to_string(j.size()) + " entries");
    }
    const Eigen::Vector3d moments = Eigen::SelfAdjointEigenSolver<Mat3<double>>(inertia).eigenvalues();
    const double total = moments.sum();
    if (!(moments.minCoeff() > 0)) {
      check_.Fail(at, "the inertia must be positive definite (principal moments " + Format(moments[0]) + ", " +
                          Format(moments[1]) + ", " + Format(moments[2]) + ")");
    }
    for (int k = 0; k < 3; ++k) {
      if (moments[k] > (total - moments[k]) * (1 + 1e-12)) {
        check_.Fail(at, "no body has this inertia: its principal moment " + Format(moments[k]) +
                            " exceeds the sum of the other two (" + Format(total - moments[k]) + ")");
      }
    }
    return inertia;
  }

  // A unit quaternion [w, x, y, z]; within 1e-6 of unit norm it is normalised, otherwise refused.
  Vec4<double> Orientation(const json& j, const std::string& at) const {
    check_.Array(j, at);
    if (j.size() != 4)
      check_.Fail(at, "expected a quaternion [w, x, y, z], got " + std::to_string(j.size()) + " numbers");
    Vec4<double> q;
    for (int k = 0; k < 4; ++k) q[k] = check_.Number(j[k], Child(at, k));
    if (!(std::abs(q.norm() - 1.0) <= 1e-6)) {
      check_.Fail(at, "a rotation is a unit quaternion: this one has norm " + Format(q.norm()));
    }
    return q / q.norm();
  }

  // A body name (or "world" when allowed) -> index.
  int BodyIndex(const json& j, const std::string& at, bool world_allowed) const {
    const std::string name = check_.String(j, at);
    if (name == "world") {
      if (!world_allowed) check_.Fail(at, "'world' cannot be used here");
      return kWorld;
    }
    auto it = names_.find(name);
    if (it == names_.end()) check_.Fail(at, "unknown body '" + name + "'");
    return it->second;
  }

  // "bodies": [A, B] and "points": [[..], [..]] of a two-body element.
  void TwoBodies(const json& element, const std::string& at, BodyPoint<double>* a, BodyPoint<double>* b) const {
    const std::string bp = Child(at, "bodies");
    const json& bodies = check_.Array(check_.Required(element, at, "bodies"), bp);
    if (bodies.size() != 2) check_.Fail(bp, "expected two body names, got " + std::to_string(bodies.size()));
    a->body = BodyIndex(bodies[0], Child(bp, 0), true);
    b->body = BodyIndex(bodies[1], Child(bp, 1), true);
    if (a->body == b->body) check_.Fail(bp, "the two bodies must differ");
    if (const json* points = check_.Optional(element, "points")) {
      const std::string pp = Child(at, "points");
      check_.Array(*points, pp);
      if (points->size() != 2) check_.Fail(pp, "expected two points, got " + std::to_string(points->size()));
      a->local = check_.Vector((*points)[0], Child(pp, 0), Dim());
      b->local = check_.Vector((*points)[1], Child(pp, 1), Dim());
    }
  }

  // World direction of a body-frame vector in the initial state, unit.
  Vec3<double> InitialDirection(int body, const Vec3<double>& local) const {
    const Vec3<double> u = local.normalized();
    return body == kWorld ? u : Vec3<double>(Rotate(model_.bodies[body].orientation, u));
  }

  // World position of a body point in the initial state.
  Vec3<double> InitialPosition(const BodyPoint<double>& p) const {
    if (p.body == kWorld) return p.local;
    const Body<double>& body = model_.bodies[p.body];
    if (body.kind == BodyKind::kParticle) return body.position + p.local;
    if (body.kind == BodyKind::kPlanar) return body.position + RotatePlanar(body.angle, p.local);
    return body.position + Rotate(body.orientation, p.local);
  }

  // A non-zero axis of `size` numbers at j.
  Vec3<double> Axis(const json& j, const std::string& at, int size) const {
    const Vec3<double> axis = check_.Vector(j, at, size);
    if (!(axis.norm() > 0)) check_.Fail(at, "the axis must not be zero");
    return axis;
  }

  // Joints that hold orientations need bodies that have one.
  void RequireOrientations(const Joint<double>& joint, const std::string& at, const std::string& type) const {
    for (int k = 0; k < 2; ++k) {
      const int body = k == 0 ? joint.a.body : joint.b.body;
      if (body != kWorld && model_.bodies[body].kind != BodyKind::kRigid3d) {
        check_.Fail(Child(Child(at, "bodies"), k), "a " + type + " joins 3D rigid bodies (or the world), and '" +
                                                       model_.bodies[body].name + "' is a particle");
      }
    }
  }

  // A double hinge's axis lines must not meet at the start: where they do, its link's invariants lose their
  // rank (constraint_rows.h), and the joint is a universal at the meeting point.
  void CheckAxisLinesApart(const Joint<double>& joint, const std::string& at) const {
    const Vec3<double> o_1 = InitialPosition(joint.a), o_2 = InitialPosition(joint.b), d = o_2 - o_1;
    const Vec3<double> a_1 = InitialDirection(joint.a.body, joint.axis);
    const Vec3<double> a_2 = InitialDirection(joint.b.body, joint.axis_b);
    const Vec3<double> normal = a_1.cross(a_2);
    const bool parallel = normal.norm() < kParallelAxes;
    const double apart = parallel ? a_1.cross(d).norm() : std::abs(d.dot(normal)) / normal.norm();
    if (!(apart > 1e-6 * d.norm())) {
      check_.Fail(at, std::string("the two axis lines ") + (parallel ? "coincide" : "meet") +
                          " at the start: a double_hinge needs them apart (" +
                          (parallel ? "two hinges on one line are one hinge"
                                    : "this is a universal joint at the point where they meet") +
                          ")");
    }
  }

  // A joint's "range" [low, high] (rad or m, either side null for open) and "restitution" e in [0, 1]: its
  // limits (unilateral_events.h). The coordinate at the start (a hinge's or pin's "angle" key, a prismatic joint's
  // displacement from the initial positions) must lie within the range.
  void ReadRange(const json& c, const std::string& at, Joint<double>* joint) const {
    const json* range = check_.Optional(c, "range");
    const json* restitution = check_.Optional(c, "restitution");
    if (!range) {
      if (restitution) check_.Fail(Child(at, "restitution"), "a restitution needs a \"range\" to act at");
      return;
    }
    const std::string rp = Child(at, "range");
    check_.Array(*range, rp);
    if (range->size() != 2) check_.Fail(rp, "expected [low, high], got " + std::to_string(range->size()) + " numbers");
    JointRange<double>& r = joint->range;
    r.has_low = !(*range)[0].is_null();
    r.has_high = !(*range)[1].is_null();
    if (r.has_low) r.low = check_.Number((*range)[0], Child(rp, 0));
    if (r.has_high) r.high = check_.Number((*range)[1], Child(rp, 1));
    if (r.has_low && r.has_high && !(r.low <= r.high)) {
      check_.Fail(rp, "low " + Format(r.low) + " must not exceed high " + Format(r.high));
    }
    if (restitution) {
      const std::string ep = Child(at, "restitution");
      r.restitution = check_.NonNegative(*restitution, ep);
      if (!(r.restitution <= 1.0)) check_.Fail(ep, "must be <= 1 (Newton's restitution), got " + Format(r.restitution));
    }
    const JointCoordinate coordinate = LimitedCoordinate(JointKindOf(joint->type));
    const bool angle = coordinate == JointCoordinate::kAngle;
    if (!HasCoordinate(model_, *joint, coordinate)) {
      check_.Fail(rp, "a 2D pin has a range only between planar rigid bodies (or one and the world), which give it "
                      "an angle");
    }
    // a start computed from positions (a displacement, an imported joint at its stop) may lie outside by rounding
    const double start = angle ? joint->angle : InitialDisplacement(*joint);
    if ((r.has_low && start < r.low - kRangeRounding) || (r.has_high && start > r.high + kRangeRounding)) {
      check_.Fail(rp, std::string("the joint's ") + (angle ? "angle " : "displacement ") + Format(start) +
                          " at the start lies outside its range");
    }
  }

  // The keys a joint of this kind takes in this scene's dimension (joint_kinds.h): an angle's "angle" at the
  // start, a limitable coordinate's "range" and "restitution" (a pin's only in 2D, where it has an angle).
  std::set<std::string> SceneKeys(const JointKind& kind) const {
    std::set<std::string> keys = {"type", "name", "bodies", "points"};
    if (kind.placing_key == JointKey::kAxis) keys.insert("axis");
    if (kind.placing_key == JointKey::kAxes) keys.insert("axes");
    if (kind.placing_key == JointKey::kLength) keys.insert("length");
    const bool angle = HasAngle(kind) && (kind.coordinates != CoordinateSet::kPlanarAngle || Dim() == 2);
    if (angle) keys.insert("angle");
    if (kind.limitable && (angle || HasDisplacement(kind))) keys.insert({"range", "restitution"});
    return keys;
  }

  // A prismatic joint's displacement (p_B - p_A) . u at the initial state, u its unit axis turned by A.
  double InitialDisplacement(const Joint<double>& joint) const {
    return InitialDirection(joint.a.body, joint.axis).dot(InitialPosition(joint.b) - InitialPosition(joint.a));
  }

  void ReadConstraints(const json& constraints) {
    check_.Array(constraints, "/constraints");
    for (size_t i = 0; i < constraints.size(); ++i) {
      const std::string at = Child("/constraints", i);
      const json& c = constraints[i];
      if (!c.is_object()) check_.Fail(at, std::string("expected an object, got ") + TypeName(c));
      const std::string type = check_.String(check_.Required(c, at, "type"), Child(at, "type"));
      const JointKind* kind = FindJointKind(type);
      if (!kind) {
        check_.Fail(Child(at, "type"), "unknown constraint type '" + type + "' (expected " + JointTypeList() + ")");
      }
      Joint<double> joint;
      joint.scene_index = static_cast<int>(i);
      joint.type = kind->type;
      check_.Object(c, at, SceneKeys(*kind));
      if (kind->spatial && Dim() != 3)
        check_.Fail(Child(at, "type"), "a " + type + " joint needs dimension 3 (in 2D a pin is the hinge)");
      joint.name = NewName(c, at, false);
      TwoBodies(c, at, &joint.a, &joint.b);
      if (kind->spatial) RequireOrientations(joint, at, type);
      if (kind->placing_key == JointKey::kAxis)
        joint.axis = Axis(check_.Required(c, at, "axis"), Child(at, "axis"), Dim());
      if (const json* angle = check_.Optional(c, "angle")) joint.angle = check_.Number(*angle, Child(at, "angle"));
      ReadRange(c, at, &joint);
      if (kind->placing_key == JointKey::kAxes) {
        const std::string ap = Child(at, "axes");
        const json& axes = check_.Array(check_.Required(c, at, "axes"), ap);
        if (axes.size() != 2)
          check_.Fail(ap, "expected two axes [in A's frame, in B's frame], got " + std::to_string(axes.size()));
        joint.axis = Axis(axes[0], Child(ap, 0), 3);
        joint.axis_b = Axis(axes[1], Child(ap, 1), 3);
      }
      if (joint.type == JointType::kDoubleHinge) CheckAxisLinesApart(joint, at);
      if (kind->placing_key == JointKey::kLength) {
        const double initial = (InitialPosition(joint.b) - InitialPosition(joint.a)).norm();
        if (!(initial > 0)) {
          check_.Fail(at, "the two points start at the same place, where the distance's direction is undefined");
        }
        const json* length = check_.Optional(c, "length");
        joint.length = length ? check_.Positive(*length, Child(at, "length")) : initial;
      }
      const int k = AddJoint(&model_, joint);
      if (!joint.name.empty()) joints_[joint.name] = k;
      BindJoint(c, at, k);
    }
  }

  // The numbers of model_.joints[k], as the constraint gives them.
  void BindJoint(const json& c, const std::string& at, int k) {
    using D = NumberDomain;
    BindPoints(
        c, at, [k](auto& m) -> auto& { return m.joints[k].a.local; },
        [k](auto& m) -> auto& { return m.joints[k].b.local; });
    if (c.contains("axis"))
      BindVector(
          Child(at, "axis"), Dim(), D::kAny, [k](auto& m) -> auto& { return m.joints[k].axis; });
    if (c.contains("axes")) {
      BindVector(
          Child(Child(at, "axes"), 0), 3, D::kAny, [k](auto& m) -> auto& { return m.joints[k].axis; });
      BindVector(
          Child(Child(at, "axes"), 1), 3, D::kAny, [k](auto& m) -> auto& { return m.joints[k].axis_b; });
    }
    if (c.contains("length"))
      Bind(
          Child(at, "length"), D::kPositive, [k](auto& m) -> auto& { return m.joints[k].length; });
    if (c.contains("angle"))
      Bind(
          Child(at, "angle"), D::kAny, [k](auto& m) -> auto& { return m.joints[k].angle; });
    const JointRange<double>& range = model_.joints[k].range;
    if (range.has_low)
      Bind(
          Child(Child(at, "range"), 0), D::kAny, [k](auto& m) -> auto& { return m.joints[k].range.low; });
    if (range.has_high) {
      Bind(
          Child(Child(at, "range"), 1), D::kAny, [k](auto& m) -> auto& { return m.joints[k].range.high; });
    }
    if (c.contains("restitution")) {
      Bind(
          Child(at, "restitution"), D::kUnitInterval, [k](auto& m) -> auto& { return m.joints[k].range.restitution; });
    }
  }

  // The rows acting on one body are coupled pairwise in the constraint solve (schur_system.h): a hub body's rows
  // form a dense block, refused up front past kMaxRowsOnOneBody rather than run out of memory.
  void CheckRowsOnEachBody() const {
    std::vector<int> rows(model_.bodies.size(), 0);
    const ConstraintSet<double> set = BuildConstraintSet(model_, InitialState(model_).q);
    for (const RowInfo& info : DescribeRows(model_, set)) {
      for (const int body : {info.body_a, info.body_b}) {
        if (body != kWorld) ++rows[body];
      }
    }
    for (size_t b = 0; b < rows.size(); ++b) {
      if (rows[b] <= kMaxRowsOnOneBody) continue;
      check_.Fail(Child("/bodies", b),
                  std::to_string(rows[b]) + " constraint rows act on body '" + model_.bodies[b].name +
                      "', more than the " + std::to_string(kMaxRowsOnOneBody) +
                      " one body may carry (the solve couples every pair of them: its memory grows with the "
                      "square of their number); split the hub into several bodies welded together");
    }
  }

  // "contact" (the law's defaults and the excluded body pairs) and "shapes", read by shape_reader.cc.
  void ReadContact(const json& contact);
  void ReadShapes(const json& shapes);
  ContactMode ContactModeNamed(const json& j, const std::string& at) const;

  void ReadMarkers(const json& markers) {
    check_.Array(markers, "/markers");
    for (size_t i = 0; i < markers.size(); ++i) {
      const std::string at = Child("/markers", i);
      const json& m = markers[i];
      if (!m.is_object()) check_.Fail(at, std::string("expected an object, got ") + TypeName(m));
      check_.Object(m, at, {"name", "body", "point"});
      Marker<double> marker;
      marker.name = NewName(m, at, true);
      marker.point.body = BodyIndex(check_.Required(m, at, "body"), Child(at, "body"), false);
      if (const json* p = check_.Optional(m, "point")) {
        marker.point.local = check_.Vector(*p, Child(at, "point"), Dim());
        const int k = static_cast<int>(model_.markers.size());
        BindVector(
            Child(at, "point"), Dim(), NumberDomain::kAny, [k](auto& m) -> auto& { return m.markers[k].point.local; });
      }
      model_.markers.push_back(marker);
    }
  }

  // A schedule {"times": [...], "values": [...]}; `size` 0 means scalar values.
  template <typename V, typename ReadValue>
  Schedule<V> ReadSchedule(const json& j, const std::string& at, ReadValue read_value) const {
    check_.Object(j, at, {"times", "values"});
    const std::string tp = Child(at, "times"), vp = Child(at, "values");
    const json& times = check_.Array(check_.Required(j, at, "times"), tp);
    const json& values = check_.Array(check_.Required(j, at, "values"), vp);
    if (times.empty()) check_.Fail(tp, "a schedule needs at least one time");
    if (values.size() != times.size()) {
      check_.Fail(vp, "expected " + std::to_string(times.size()) + " values (one per time), got " +
                          std::to_string(values.size()));
    }
    Schedule<V> s;
    for (size_t k = 0; k < times.size(); ++k) {
      s.times.push_back(check_.Number(times[k], Child(tp, k)));
      if (k > 0 && !(s.times[k] > s.times[k - 1])) check_.Fail(Child(tp, k), "times must increase strictly");
      s.values.push_back(read_value(values[k], Child(vp, k)));
    }
    return s;
  }

  std::vector<int> AllBodies() const {
    std::vector<int> all(model_.bodies.size());
    for (size_t i = 0; i < all.size(); ++i) all[i] = static_cast<int>(i);
    return all;
  }

  // The effects, each type read by its row of the reader's table (effect_reader.cc), which uses the helpers above.
  void ReadEffects(const json& effects);

  // "joint": NAME and "coordinate" (required for a cylindrical joint, else the joint's only coordinate).
  void ReadJointReference(const json& e, const std::string& at, int* joint, JointCoordinate* coordinate) const {
    const std::string jp = Child(at, "joint");
    const std::string name = check_.String(check_.Required(e, at, "joint"), jp);
    const auto it = joints_.find(name);
    if (it == joints_.end()) check_.Fail(jp, "no constraint is named '" + name + "'");
    *joint = it->second;
    const Joint<double>& j = model_.joints[*joint];
    const bool angle = HasCoordinate(model_, j, JointCoordinate::kAngle);
    const bool displacement = HasCoordinate(model_, j, JointCoordinate::kDisplacement);
    if (!angle && !displacement) {
      check_.Fail(jp, "the " + std::string(JointTypeName(j.type)) + " '" + name +
                          "' has no coordinate to drive (hinges, prismatic and cylindrical joints, and in 2D pins "
                          "between rigid bodies, have one)");
    }
    const std::string cp = Child(at, "coordinate");
    if (const json* c = check_.Optional(e, "coordinate")) {
      const std::string value = check_.String(*c, cp);
      if (value != "angle" && value != "displacement") {
        check_.Fail(cp, "unknown coordinate '" + value + "' (expected angle or displacement)");
      }
      *coordinate = value == "angle" ? JointCoordinate::kAngle : JointCoordinate::kDisplacement;
      if (!HasCoordinate(model_, j, *coordinate)) {
        check_.Fail(cp, "the " + std::string(JointTypeName(j.type)) + " '" + name + "' has no " + value);
      }
    } else if (angle && displacement) {
      check_.Fail(at, "the cylindrical joint '" + name + "' has two coordinates: say which with \"coordinate\"");
    } else {
      *coordinate = angle ? JointCoordinate::kAngle : JointCoordinate::kDisplacement;
    }
  }

  // An effect's `key` ("value", a servo's "target") or "schedule" (exactly one), each entry read by read_value.
  template <typename V, typename ReadValue>
  void ReadValueOrSchedule(const json& e, const std::string& at, ReadValue read_value, V* value, Schedule<V>* schedule,
                           const std::string& key = "value") const {
    if (e.contains(key) == e.contains("schedule")) check_.Fail(at, "give exactly one of '" + key + "' and 'schedule'");
    if (const json* v = check_.Optional(e, key.c_str())) {
      *value = read_value(*v, Child(at, key));
    } else {
      *schedule = ReadSchedule<V>(e.at("schedule"), Child(at, "schedule"), read_value);
    }
  }

  void ReadSimulation(const json& s) {
    check_.Object(s, "/simulation", {"integrator", "step", "duration", "tolerance", "solver", "contact"});
    SimulationSettings& sim = model_.simulation;
    if (const json* i = check_.Optional(s, "integrator")) {
      sim.integrator =
          ParseIntegrator(check_.String(*i, "/simulation/integrator"), check_.Where("/simulation/integrator"));
    }
    if (const json* h = check_.Optional(s, "step")) sim.step = check_.Positive(*h, "/simulation/step");
    if (const json* t = check_.Optional(s, "duration")) sim.duration = check_.Positive(*t, "/simulation/duration");
    if (const json* t = check_.Optional(s, "tolerance")) sim.tolerance = check_.Positive(*t, "/simulation/tolerance");
    if (const json* k = check_.Optional(s, "solver")) {
      sim.solver = ParseKktSolver(check_.String(*k, "/simulation/solver"), check_.Where("/simulation/solver"));
    }
    if (const json* c = check_.Optional(s, "contact")) sim.contact = ContactModeNamed(*c, "/simulation/contact");
    CheckStepCount(sim, check_.Where("/simulation/duration"));
  }

  void ReadStabilization(const json& s) {
    check_.Object(s, "/stabilization", {"method", "alpha", "beta"});
    StabilizationSettings<double>& st = model_.stabilization;
    if (const json* m = check_.Optional(s, "method")) {
      st.method = ParseStabilization(check_.String(*m, "/stabilization/method"), check_.Where("/stabilization/method"));
    }
    const json* alpha = check_.Optional(s, "alpha");
    const json* beta = check_.Optional(s, "beta");
    if (!alpha && !beta) return;
    if (st.method != Stabilization::kBaumgarte) {
      check_.Fail(alpha ? "/stabilization/alpha" : "/stabilization/beta", "gains apply to the baumgarte method only");
    }
    if (!alpha || !beta) {
      check_.Fail("/stabilization", "give both 'alpha' and 'beta', or neither (the default rule then sets both)");
    }
    st.alpha = check_.NonNegative(*alpha, "/stabilization/alpha");
    st.beta = check_.NonNegative(*beta, "/stabilization/beta");
    Bind(
        "/stabilization/alpha", NumberDomain::kNonNegative, [](auto& m) -> auto& { return m.stabilization.alpha; });
    Bind(
        "/stabilization/beta", NumberDomain::kNonNegative, [](auto& m) -> auto& { return m.stabilization.beta; });
    st.gains_from_rule = false;
  }

 private:
  const json& doc_;
  Validator check_;
  Model<double> model_;
  SceneNumbers numbers_;
  std::map<std::string, int> names_;              // body name -> index
  std::map<std::string, int> joints_;             // constraint name -> index in model_.joints
  std::map<std::string, std::string> all_names_;  // every name -> where it was given
};

}  // namespace tether::reading
