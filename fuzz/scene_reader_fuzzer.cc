// libFuzzer target for the scene reader: the bytes of a scene file go through the same entry points as
// ReadSceneFile (what every tether command uses), ParseJsonText then ParseScene.
//
// What may happen: the scene is accepted, or an InputError is thrown whose message starts with the file name
// (the header's promise: "FILE: POINTER: ..." or "FILE: line L, column C: ..."). Anything else is a finding:
// another exception (it would escape the CLI's handler for input errors), a crash, a sanitizer report, or an
// accepted scene that breaks the invariants the simulator relies on (checked below).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "tether/dynamics/effects/effects.h"
#include "tether/dynamics/io/scene_reader.h"
#include "tether/dynamics/model/configuration_space.h"
#include "tether/dynamics/model/errors.h"

namespace {

const char kPath[] = "fuzz.json";

[[noreturn]] void Finding(const std::string& what) {
  std::fprintf(stderr, "scene_reader_fuzzer: %s\n", what.c_str());
  std::abort();
}

bool Finite(const tether::Vec3<double>& v) { return v.allFinite(); }

// A body index as the model stores it: a body, or kWorld where the world is allowed.
bool ValidBody(const tether::Model<double>& model, int body, bool world_allowed) {
  return (world_allowed && body == tether::kWorld) || (body >= 0 && body < static_cast<int>(model.bodies.size()));
}

void CheckModel(const tether::Model<double>& model) {
  if (model.dimension != 2 && model.dimension != 3) Finding("dimension " + std::to_string(model.dimension));
  if (model.bodies.empty()) Finding("a scene without bodies was accepted");
  int q_offset = 0, v_offset = 0;
  for (const tether::Body<double>& body : model.bodies) {
    if (body.name.empty() || body.name == "world") Finding("body name '" + body.name + "' was accepted");
    if (!(body.mass > 0) || !std::isfinite(body.mass)) Finding("body mass not finite and positive");
    const bool planar = body.kind == tether::BodyKind::kPlanar;
    const bool spatial = body.kind == tether::BodyKind::kRigid3d;
    if (planar && (!(body.inertia > 0) || !std::isfinite(body.inertia))) Finding("planar inertia not positive");
    if (spatial && !(tether::PrincipalInertia(body).diagonal().minCoeff() > 0)) Finding("3D inertia not positive");
    if (body.q_offset != q_offset || body.v_offset != v_offset) Finding("body offsets are not contiguous");
    const int size = planar ? 3 : model.dimension;
    if (body.q_size != (spatial ? 7 : size) || body.v_size != (spatial ? 6 : size)) {
      Finding("body size " + std::to_string(body.q_size));
    }
    q_offset += body.q_size;
    v_offset += body.v_size;
  }
  const tether::State<double> start = tether::InitialState(model);
  if (start.q.size() != q_offset || start.v.size() != v_offset) Finding("the initial state does not match the bodies");
  if (!start.q.allFinite() || !start.v.allFinite()) Finding("non-finite initial state");
  for (const auto& c : model.joints) {
    if (!ValidBody(model, c.a.body, true) || !ValidBody(model, c.b.body, true) || c.a.body == c.b.body) {
      Finding(std::string(tether::JointTypeName(c.type)) + " constraint with bad bodies");
    }
    if (!Finite(c.a.local) || !Finite(c.b.local)) Finding("non-finite constraint point");
    if (c.type == tether::JointType::kDistance && (!(c.length > 0) || !std::isfinite(c.length))) {
      Finding("distance length not finite and positive");
    }
    if (!Finite(c.axis) || !(c.axis.norm() > 0) || !Finite(c.axis_b) || !(c.axis_b.norm() > 0)) {
      Finding("constraint axis zero or non-finite");
    }
  }
  for (const auto& m : model.markers) {
    if (!ValidBody(model, m.point.body, false) || !Finite(m.point.local)) Finding("marker with a bad body or point");
  }
  for (const auto& e : model.joint_torques) {
    if (e.joint < 0 || e.joint >= static_cast<int>(model.joints.size()) ||
        !tether::HasCoordinate(model, model.joints[e.joint], e.coordinate)) {
      Finding("motor on a joint without that coordinate");
    }
  }
  for (const auto& e : model.joint_springs) {
    if (e.joint < 0 || e.joint >= static_cast<int>(model.joints.size()) ||
        !tether::HasCoordinate(model, model.joints[e.joint], e.coordinate)) {
      Finding("joint spring on a joint without that coordinate");
    }
    if (!(e.stiffness >= 0) || !(e.damping >= 0)) Finding("negative joint spring parameter");
  }
  for (const auto& e : model.joint_servos) {
    if (e.joint < 0 || e.joint >= static_cast<int>(model.joints.size()) ||
        !tether::HasCoordinate(model, model.joints[e.joint], e.coordinate)) {
      Finding("servo on a joint without that coordinate");
    }
    if (!(e.kp >= 0) || !(e.kd >= 0) || !(e.limit >= 0)) Finding("negative servo parameter");
    if (e.schedule.times.size() != e.schedule.values.size()) Finding("servo schedule sizes differ");
  }
  for (const auto& g : model.gravity) {
    if (!Finite(g.acceleration)) Finding("non-finite gravity");
  }
  for (const auto& d : model.damping) {
    if (!(d.coefficient >= 0) || !(d.angular_coefficient >= 0)) Finding("negative damping");
    for (int body : d.bodies) {
      if (!ValidBody(model, body, false)) Finding("damping on a bad body");
    }
  }
  for (const auto& s : model.springs) {
    if (!ValidBody(model, s.a.body, true) || !ValidBody(model, s.b.body, true)) Finding("spring with bad bodies");
    if (!(s.stiffness >= 0) || !(s.rest_length >= 0) || !(s.damping >= 0)) Finding("negative spring parameter");
  }
  for (const auto& f : model.forces) {
    if (!ValidBody(model, f.body, false)) Finding("force on a bad body");
    if (f.schedule.times.size() != f.schedule.values.size()) Finding("force schedule sizes differ");
    for (size_t k = 1; k < f.schedule.times.size(); ++k) {
      if (!(f.schedule.times[k] > f.schedule.times[k - 1])) Finding("force schedule times not increasing");
    }
  }
  for (const auto& t : model.torques) {
    if (!ValidBody(model, t.body, false)) Finding("torque on a bad body");
    if (model.bodies[t.body].kind == tether::BodyKind::kParticle) Finding("torque on a particle");
    if (t.schedule.times.size() != t.schedule.values.size()) Finding("torque schedule sizes differ");
  }
  const tether::SimulationSettings& sim = model.simulation;
  if (!(sim.step > 0) || !(sim.duration > 0) || !(sim.tolerance > 0) || !std::isfinite(sim.step) ||
      !std::isfinite(sim.duration) || !std::isfinite(sim.tolerance)) {
    Finding("simulation settings not finite and positive");
  }
  const auto& st = model.stabilization;
  if (!(st.alpha >= 0) || !(st.beta >= 0) || !std::isfinite(st.alpha) || !std::isfinite(st.beta)) {
    Finding("stabilization gains not finite and non-negative");
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const tether::Scene scene = tether::ParseScene(tether::ParseJsonText(text, kPath), kPath);
    CheckModel(scene.model);
  } catch (const tether::InputError& e) {
    const std::string message = e.what();
    if (message.rfind(std::string(kPath) + ": ", 0) != 0) Finding("an input error that does not name the file: " + message);
  }
  return 0;
}
