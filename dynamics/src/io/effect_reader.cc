// The reader's table of effects: each scene "type" of docs/scene-format.md's effects and the function that reads
// it into its list of the model (model.h), binding every number it reads to the field it lands in
// (scene_numbers.h: that is what makes the number a parameter). Adding an effect adds its function and its row
// here (docs/architecture.md, "Add an effect").
#include "scene_builder.h"

namespace tether::reading {
namespace {

using D = NumberDomain;

void ReadGravity(SceneBuilder& r, const json& e, const std::string& at, int index) {
  r.check().Object(e, at, {"type", "acceleration"});
  const int k = static_cast<int>(r.model().gravity.size());
  const std::string ap = Child(at, "acceleration");
  r.model().gravity.push_back({index, r.check().Vector(r.check().Required(e, at, "acceleration"), ap, r.Dim())});
  r.BindVector(
      ap, r.Dim(), D::kAny, [k](auto& m) -> auto& { return m.gravity[k].acceleration; });
}

void ReadDamping(SceneBuilder& r, const json& e, const std::string& at, int index) {
  r.check().Object(e, at, {"type", "coefficient", "angular_coefficient", "bodies"});
  const int k = static_cast<int>(r.model().damping.size());
  DampingEffect<double> d;
  d.scene_index = index;
  d.coefficient = r.check().NonNegative(r.check().Required(e, at, "coefficient"), Child(at, "coefficient"));
  r.Bind(
      Child(at, "coefficient"), D::kNonNegative, [k](auto& m) -> auto& { return m.damping[k].coefficient; });
  if (const json* c = r.check().Optional(e, "angular_coefficient")) {
    d.angular_coefficient = r.check().NonNegative(*c, Child(at, "angular_coefficient"));
    r.Bind(
        Child(at, "angular_coefficient"),
        D::kNonNegative, [k](auto& m) -> auto& { return m.damping[k].angular_coefficient; });
  }
  if (const json* list = r.check().Optional(e, "bodies")) {
    const std::string bp = Child(at, "bodies");
    r.check().Array(*list, bp);
    for (size_t b = 0; b < list->size(); ++b) d.bodies.push_back(r.BodyIndex((*list)[b], Child(bp, b), false));
  } else {
    d.bodies = r.AllBodies();
  }
  r.model().damping.push_back(d);
}

void ReadSpring(SceneBuilder& r, const json& e, const std::string& at, int index) {
  r.check().Object(e, at, {"type", "bodies", "points", "stiffness", "rest_length", "damping"});
  const int k = static_cast<int>(r.model().springs.size());
  SpringEffect<double> s;
  s.scene_index = index;
  r.TwoBodies(e, at, &s.a, &s.b);
  r.BindPoints(
      e, at, [k](auto& m) -> auto& { return m.springs[k].a.local; },
      [k](auto& m) -> auto& { return m.springs[k].b.local; });
  s.stiffness = r.check().NonNegative(r.check().Required(e, at, "stiffness"), Child(at, "stiffness"));
  r.Bind(
      Child(at, "stiffness"), D::kNonNegative, [k](auto& m) -> auto& { return m.springs[k].stiffness; });
  s.rest_length = r.check().NonNegative(r.check().Required(e, at, "rest_length"), Child(at, "rest_length"));
  r.Bind(
      Child(at, "rest_length"), D::kNonNegative, [k](auto& m) -> auto& { return m.springs[k].rest_length; });
  if (const json* d = r.check().Optional(e, "damping")) {
    s.damping = r.check().NonNegative(*d, Child(at, "damping"));
    r.Bind(
        Child(at, "damping"), D::kNonNegative, [k](auto& m) -> auto& { return m.springs[k].damping; });
  }
  if (!((r.InitialPosition(s.b) - r.InitialPosition(s.a)).norm() > 0)) {
    r.check().Fail(at, "the spring's two points start at the same place, where its direction is undefined");
  }
  r.model().springs.push_back(s);
}

void ReadForce(SceneBuilder& r, const json& e, const std::string& at, int index) {
  r.check().Object(e, at, {"type", "body", "point", "value", "schedule"});
  const int k = static_cast<int>(r.model().forces.size());
  ForceEffect<double> f;
  f.scene_index = index;
  f.body = r.BodyIndex(r.check().Required(e, at, "body"), Child(at, "body"), false);
  if (const json* p = r.check().Optional(e, "point")) {
    f.point = r.check().Vector(*p, Child(at, "point"), r.Dim());
    r.BindVector(
        Child(at, "point"), r.Dim(), D::kAny, [k](auto& m) -> auto& { return m.forces[k].point; });
  }
  r.ReadValueOrSchedule(
      e, at, [&r](const json& j, const std::string& p) { return r.check().Vector(j, p, r.Dim()); }, &f.value,
      &f.schedule);
  if (f.schedule.empty()) {
    r.BindVector(
        Child(at, "value"), r.Dim(), D::kAny, [k](auto& m) -> auto& { return m.forces[k].value; });
  }
  r.BindSchedule(at, f.schedule.times, [&r, k](const std::string& p, int j, const ScheduleKnot& knot) {
    r.BindVector(
        p, r.Dim(), D::kAny, [ k, j ](auto& m) -> auto& { return m.forces[k].schedule.values[j]; }, knot);
  });
  r.model().forces.push_back(f);
}

void ReadTorque(SceneBuilder& r, const json& e, const std::string& at, int index) {
  r.check().Object(e, at, {"type", "body", "value", "schedule"});
  const int k = static_cast<int>(r.model().torques.size());
  TorqueEffect<double> t;
  t.scene_index = index;
  t.body = r.BodyIndex(r.check().Required(e, at, "body"), Child(at, "body"), false);
  if (r.model().bodies[t.body].kind == BodyKind::kParticle) {
    r.check().Fail(Child(at, "body"),
                   "a torque acts on a rigid body, and '" + r.model().bodies[t.body].name + "' is a particle");
  }
  const bool planar = r.Dim() == 2;
  auto read = [&r, planar](const json& j, const std::string& p) {  // planar: a number about z; 3D: a vector
    if (planar) return Vec3<double>(0.0, 0.0, r.check().Number(j, p));
    return r.check().Vector(j, p, 3);
  };
  r.ReadValueOrSchedule(e, at, read, &t.value, &t.schedule);
  if (t.schedule.empty() && planar) {
    r.Bind(
        Child(at, "value"), D::kAny, [k](auto& m) -> auto& { return m.torques[k].value[2]; });
  } else if (t.schedule.empty()) {
    r.BindVector(
        Child(at, "value"), 3, D::kAny, [k](auto& m) -> auto& { return m.torques[k].value; });
  }
  r.BindSchedule(at, t.schedule.times, [&r, k, planar](const std::string& p, int j, ScheduleKnot knot) {
    if (!planar) {
      r.BindVector(
          p, 3, D::kAny, [ k, j ](auto& m) -> auto& { return m.torques[k].schedule.values[j]; }, knot);
      return;
    }
    knot.component = 2;
    r.Bind(
        p, D::kAny, [ k, j ](auto& m) -> auto& { return m.torques[k].schedule.values[j][2]; }, knot);
  });
  r.model().torques.push_back(t);
}

void ReadJointTorque(SceneBuilder& r, const json& e, const std::string& at, int index) {
  r.check().Object(e, at, {"type", "joint", "coordinate", "value", "schedule"});
  const int k = static_cast<int>(r.model().joint_torques.size());
  JointTorqueEffect<double> t;
  t.scene_index = index;
  r.ReadJointReference(e, at, &t.joint, &t.coordinate);
  r.ReadValueOrSchedule(
      e, at, [&r](const json& j, const std::string& p) { return r.check().Number(j, p); }, &t.value, &t.schedule);
  if (t.schedule.empty()) {
    r.Bind(
        Child(at, "value"), D::kAny, [k](auto& m) -> auto& { return m.joint_torques[k].value; });
  }
  r.BindSchedule(at, t.schedule.times, [&r, k](const std::string& p, int j, const ScheduleKnot& knot) {
    r.Bind(
        p, D::kAny, [ k, j ](auto& m) -> auto& { return m.joint_torques[k].schedule.values[j]; }, knot);
  });
  r.model().joint_torques.push_back(t);
}

void ReadJointSpring(SceneBuilder& r, const json& e, const std::string& at, int index) {
  r.check().Object(e, at, {"type", "joint", "coordinate", "stiffness", "rest", "damping"});
  const int k = static_cast<int>(r.model().joint_springs.size());
  JointSpringEffect<double> s;
  s.scene_index = index;
  r.ReadJointReference(e, at, &s.joint, &s.coordinate);
  s.stiffness = r.check().NonNegative(r.check().Required(e, at, "stiffness"), Child(at, "stiffness"));
  r.Bind(
      Child(at, "stiffness"), D::kNonNegative, [k](auto& m) -> auto& { return m.joint_springs[k].stiffness; });
  if (const json* rest = r.check().Optional(e, "rest")) {
    s.rest = r.check().Number(*rest, Child(at, "rest"));
    r.Bind(
        Child(at, "rest"), D::kAny, [k](auto& m) -> auto& { return m.joint_springs[k].rest; });
  }
  if (const json* d = r.check().Optional(e, "damping")) {
    s.damping = r.check().NonNegative(*d, Child(at, "damping"));
    r.Bind(
        Child(at, "damping"), D::kNonNegative, [k](auto& m) -> auto& { return m.joint_springs[k].damping; });
  }
  r.model().joint_springs.push_back(s);
}

void ReadJointServo(SceneBuilder& r, const json& e, const std::string& at, int index) {
  r.check().Object(e, at, {"type", "joint", "coordinate", "kp", "kd", "target", "schedule", "target_rate", "limit"});
  const int k = static_cast<int>(r.model().joint_servos.size());
  JointServoEffect<double> s;
  s.scene_index = index;
  r.ReadJointReference(e, at, &s.joint, &s.coordinate);
  s.kp = r.check().NonNegative(r.check().Required(e, at, "kp"), Child(at, "kp"));
  r.Bind(
      Child(at, "kp"), D::kNonNegative, [k](auto& m) -> auto& { return m.joint_servos[k].kp; });
  s.kd = r.check().NonNegative(r.check().Required(e, at, "kd"), Child(at, "kd"));
  r.Bind(
      Child(at, "kd"), D::kNonNegative, [k](auto& m) -> auto& { return m.joint_servos[k].kd; });
  r.ReadValueOrSchedule(
      e, at, [&r](const json& j, const std::string& p) { return r.check().Number(j, p); }, &s.target, &s.schedule,
      "target");
  if (s.schedule.empty()) {
    r.Bind(
        Child(at, "target"), D::kAny, [k](auto& m) -> auto& { return m.joint_servos[k].target; });
  }
  r.BindSchedule(at, s.schedule.times, [&r, k](const std::string& p, int j, const ScheduleKnot& knot) {
    r.Bind(
        p, D::kAny, [ k, j ](auto& m) -> auto& { return m.joint_servos[k].schedule.values[j]; }, knot);
  });
  if (const json* rate = r.check().Optional(e, "target_rate")) {
    s.target_rate = r.check().Number(*rate, Child(at, "target_rate"));
    r.Bind(
        Child(at, "target_rate"), D::kAny, [k](auto& m) -> auto& { return m.joint_servos[k].target_rate; });
  }
  if (const json* limit = r.check().Optional(e, "limit")) {
    s.limit = r.check().Positive(*limit, Child(at, "limit"));
    r.Bind(
        Child(at, "limit"), D::kPositive, [k](auto& m) -> auto& { return m.joint_servos[k].limit; });
  }
  r.model().joint_servos.push_back(s);
}

void ReadDrag(SceneBuilder& r, const json& e, const std::string& at, int index) {
  r.check().Object(e, at, {"type", "body", "point", "density", "drag_coefficient", "area"});
  const int k = static_cast<int>(r.model().drag.size());
  DragEffect<double> d;
  d.scene_index = index;
  d.body = r.BodyIndex(r.check().Required(e, at, "body"), Child(at, "body"), false);
  if (const json* p = r.check().Optional(e, "point")) {
    d.point = r.check().Vector(*p, Child(at, "point"), r.Dim());
    r.BindVector(
        Child(at, "point"), r.Dim(), D::kAny, [k](auto& m) -> auto& { return m.drag[k].point; });
  }
  if (const json* rho = r.check().Optional(e, "density")) {
    d.density = r.check().NonNegative(*rho, Child(at, "density"));
    r.Bind(
        Child(at, "density"), D::kNonNegative, [k](auto& m) -> auto& { return m.drag[k].density; });
  }
  const std::string cp = Child(at, "drag_coefficient"), ap = Child(at, "area");
  d.drag_coefficient = r.check().NonNegative(r.check().Required(e, at, "drag_coefficient"), cp);
  r.Bind(
      cp, D::kNonNegative, [k](auto& m) -> auto& { return m.drag[k].drag_coefficient; });
  d.area = r.check().NonNegative(r.check().Required(e, at, "area"), ap);
  r.Bind(
      ap, D::kNonNegative, [k](auto& m) -> auto& { return m.drag[k].area; });
  r.model().drag.push_back(d);
}

struct EffectReader {
  const char* type;  // the scene's "type"
  void (*read)(SceneBuilder&, const json& effect, const std::string& at, int index);
};

// The table: one row an effect type, in the order docs/scene-format.md lists them.
// clang-format off
constexpr EffectReader kEffectReaders[] = {
    {"gravity", ReadGravity},
    {"damping", ReadDamping},
    {"spring", ReadSpring},
    {"force", ReadForce},
    {"torque", ReadTorque},
    {"joint_torque", ReadJointTorque},
    {"joint_spring", ReadJointSpring},
    {"joint_servo", ReadJointServo},
    {"drag", ReadDrag},
};
// clang-format on

}  // namespace

void SceneBuilder::ReadEffects(const json& effects) {
  check_.Array(effects, "/effects");
  for (size_t i = 0; i < effects.size(); ++i) {
    const std::string at = Child("/effects", i);
    const json& e = effects[i];
    if (!e.is_object()) check_.Fail(at, std::string("expected an object, got ") + TypeName(e));
    const std::string type = check_.String(check_.Required(e, at, "type"), Child(at, "type"));
    const EffectReader* reader = nullptr;
    for (const EffectReader& row : kEffectReaders) {
      if (type == row.type) reader = &row;
    }
    if (!reader) {
      std::vector<std::string> types;
      for (const EffectReader& row : kEffectReaders) types.push_back(row.type);
      check_.Fail(Child(at, "type"), "unknown effect type '" + type + "' (expected " + ListWithOr(types) + ")");
    }
    reader->read(*this, e, at, static_cast<int>(i));
  }
}

}  // namespace tether::reading
