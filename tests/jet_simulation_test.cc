// Whole simulations with T = Jet (docs/architecture.md, principle 1: one templated code path), for a damped pendulum, a
// rigid four-bar on pins and a slider + spring + damping oscillator, under every integrator and every
// stabilization. Four derivative directions are seeded on model fields (masses, lengths, gravity, stiffness,
// damping, initial velocities). Checked at every output row, positions and velocities:
//   (1) the value part of the Jet run equals the double run to round-off;
//   (2) the derivative parts equal central differences of double runs with the field perturbed.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>
#include <tuple>
#include <vector>

#include "tether/dynamics/integration/simulator.h"
#include "tether/dynamics/model/kinematics.h"

namespace tether {
namespace {

constexpr double kValueTolerance = 1e-12;  // Jet value part vs double run, relative to max(1, |x|)
constexpr double kDerivativeTolerance = 1e-6;  // vs central differences, relative to the largest sensitivity
constexpr double kRelativeStep = 1e-5;         // central-difference step, relative to max(1, |parameter|)
constexpr double kRk45Tolerance = 1e-10;       // tight, so that step-size control does not differ between runs

// A model field that a derivative direction is seeded on, reachable for both scalars.
struct Parameter {
  std::string name;
  std::function<double&(Model<double>&)> in_double;
  std::function<Jet&(Model<Jet>&)> in_jet;
};
#define TETHER_PARAMETER(expression)                                                                                 \
  Parameter {                                                                                                        \
#expression,                                                                                                     \
        [](Model <double> & m) -> double& { return expression; }, [](Model <Jet> & m) -> Jet& { return expression; } \
  }

struct Scene {
  Model<double> model;
  std::vector<Parameter> parameters;  // kJetStride of them
};

Model<double> Planar(double gravity_x, double gravity_y) {
  Model<double> model;
  model.dimension = 2;
  model.gravity.push_back({0, Vec3<double>(gravity_x, gravity_y, 0.0)});
  model.simulation.step = 2e-3;
  model.simulation.duration = 0.6;
  return model;
}

// A 1 kg bob on a 0.7 m rod from 60 degrees, moving, with viscous damping (so that the mass matters).
Scene DampedPendulum() {
  Model<double> model = Planar(0.0, -9.81);
  const double length = 0.7, angle = M_PI / 3, speed = 0.8;
  const int bob = AddBody<double>(&model, "bob", BodyKind::kParticle, 1.0, 0.0,
                                  Vec3<double>(length * std::sin(angle), -length * std::cos(angle), 0.0), 0.0,
                                  Vec3<double>(speed * std::cos(angle), speed * std::sin(angle), 0.0), 0.0);
  Joint<double> rod;
  rod.scene_index = 0;
  rod.type = JointType::kDistance;
  rod.a = {kWorld, Vec3<double>::Zero()};
  rod.b = {bob, Vec3<double>::Zero()};
  rod.length = length;
  AddJoint(&model, rod);
  model.damping.push_back({1, 0.4, 0.0, {bob}});
  return {model,
          {TETHER_PARAMETER(m.bodies[0].mass), TETHER_PARAMETER(m.joints[0].length),
           TETHER_PARAMETER(m.gravity[0].acceleration[1]), TETHER_PARAMETER(m.bodies[0].velocity[0])}};
}

// A Grashof crank-rocker (ground 1.0, crank 0.4, coupler 1.1, rocker 0.8 m): the crank turns fully without a
// singular configuration. Bars are rigid bodies centred between their pins; the crank starts turning at 3 rad/s.
Scene FourBar() {
  Model<double> model = Planar(0.0, -9.81);
  const double crank = 0.4, coupler = 1.1, rocker = 0.8, start = 1.0;
  const Vec3<double> ground(1.0, 0.0, 0.0);
  const Vec3<double> b = crank * Vec3<double>(std::cos(start), std::sin(start), 0.0);
  // c: the upper intersection of the circles |c - b| = coupler and |c - ground| = rocker
  const Vec3<double> bd = ground - b;
  const double dist = bd.norm(), along = (coupler * coupler - rocker * rocker + dist * dist) / (2 * dist);
  const double across = std::sqrt(coupler * coupler - along * along);
  const Vec3<double> c = b + along * bd / dist + across * Perp(Vec3<double>(bd / dist));
  auto add_bar = [&model](const std::string& name, const Vec3<double>& from, const Vec3<double>& to, double mass) {
    const Vec3<double> d = to - from;
    return AddBody<double>(&model, name, BodyKind::kPlanar, mass, mass * d.squaredNorm() / 12.0, 0.5 * (from + to),
                           std::atan2(d.y(), d.x()), Vec3<double>::Zero(), 0.0);
  };
  const int k_crank = add_bar("crank", Vec3<double>::Zero(), b, 0.5);
  const int k_coupler = add_bar("coupler", b, c, 1.2);
  const int k_rocker = add_bar("rocker", ground, c, 0.9);
  model.bodies[k_crank].angular_velocity.z() = 3.0;
  auto pin = [&model](int a, const Vec3<double>& at_a, int b_body, const Vec3<double>& at_b) {
    Joint<double> joint;
    joint.scene_index = model.NumConstraints();
    joint.type = JointType::kPin;
    joint.a = {a, at_a};
    joint.b = {b_body, at_b};
    AddJoint(&model, joint);
  };
  auto along_bar = [](double x) { return Vec3<double>(x, 0.0, 0.0); };
  pin(kWorld, Vec3<double>::Zero(), k_crank, along_bar(-crank / 2));
  pin(k_crank, along_bar(crank / 2), k_coupler, along_bar(-coupler / 2));
  pin(k_coupler, along_bar(coupler / 2), k_rocker, along_bar(rocker / 2));
  pin(k_rocker, along_bar(-rocker / 2), kWorld, ground);
  return {model,
          {TETHER_PARAMETER(m.bodies[0].mass), TETHER_PARAMETER(m.bodies[2].inertia),
           TETHER_PARAMETER(m.gravity[0].acceleration[1]), TETHER_PARAMETER(m.bodies[0].angular_velocity[2])}};
}

// A particle on a slider through the origin along (1, 0.5), pulled by a damped spring from a world point on
// the line behind it, with viscous damping and gravity (which has a component along the slider).
Scene SliderOscillator() {
  Model<double> model = Planar(0.0, -9.81);
  const Vec3<double> axis = Vec3<double>(1.0, 0.5, 0.0).normalized();
  const int cart = AddBody<double>(&model, "cart", BodyKind::kParticle, 0.8, 0.0, Vec3<double>(0.8 * axis), 0.0,
                                   Vec3<double>(0.3 * axis), 0.0);
  Joint<double> slider;
  slider.scene_index = 0;
  slider.type = JointType::kSlider;
  slider.a = {kWorld, Vec3<double>::Zero()};
  slider.b = {cart, Vec3<double>::Zero()};
  slider.axis = axis;
  AddJoint(&model, slider);
  model.springs.push_back({1, {kWorld, Vec3<double>(-axis)}, {cart, Vec3<double>::Zero()}, 40.0, 1.5, 0.5});
  model.damping.push_back({2, 0.3, 0.0, {cart}});
  return {model,
          {TETHER_PARAMETER(m.bodies[0].mass), TETHER_PARAMETER(m.springs[0].stiffness),
           TETHER_PARAMETER(m.damping[0].coefficient), TETHER_PARAMETER(m.bodies[0].velocity[0])}};
}

template <typename T>
struct Trajectory {
  std::vector<VecX<T>> q, v;
};

template <typename T>
Trajectory<T> Simulated(const Model<T>& model) {
  Trajectory<T> out;
  Simulate<T>(model, RunOptions{5}, [&out](const Sample<T>& s) {
    out.q.push_back(s.q);
    out.v.push_back(s.v);
  });
  return out;
}

enum class SceneKind { kPendulum, kFourBar, kSliderOscillator };
using Combination = std::tuple<SceneKind, Integrator, Stabilization>;

class JetSimulation : public ::testing::TestWithParam<Combination> {};

// Compares the Jet run with the double runs for one state component series (q or v).
void Compare(const std::vector<VecX<Jet>>& jet, const std::vector<VecX<double>>& value,
             const std::vector<std::vector<VecX<double>>>& differences, const Scene& scene, double value_tolerance,
             const char* what) {
  ASSERT_EQ(jet.size(), value.size()) << what;
  for (size_t t = 0; t < jet.size(); ++t) {
    for (int i = 0; i < jet[t].size(); ++i) {
      EXPECT_NEAR(jet[t][i].a, value[t][i], value_tolerance * std::max(1.0, std::abs(value[t][i])))
          << what << " value, row " << t << ", coordinate " << i;
    }
  }
  for (int k = 0; k < kJetStride; ++k) {
    const std::vector<VecX<double>>& fd = differences[k];
    ASSERT_EQ(fd.size(), jet.size()) << what;
    double scale = 1.0;
    for (const VecX<double>& row : fd) scale = std::max(scale, row.cwiseAbs().maxCoeff());
    for (size_t t = 0; t < jet.size(); ++t) {
      for (int i = 0; i < jet[t].size(); ++i) {
        EXPECT_NEAR(jet[t][i].v[k], fd[t][i], kDerivativeTolerance * scale)
            << what << " d/d " << scene.parameters[k].name << ", row " << t << ", coordinate " << i;
      }
    }
  }
}

TEST_P(JetSimulation, ValuesMatchDoubleAndDerivativesMatchDifferences) {
  const auto [kind, integrator, stabilization] = GetParam();
  Scene scene = kind == SceneKind::kPendulum  ? DampedPendulum()
                : kind == SceneKind::kFourBar ? FourBar()
                                              : SliderOscillator();
  scene.model.simulation.integrator = integrator;
  scene.model.simulation.tolerance = kRk45Tolerance;
  scene.model.stabilization.method = stabilization;
  ASSERT_EQ(static_cast<int>(scene.parameters.size()), kJetStride);

  Model<Jet> seeded = CastModel<Jet>(scene.model);
  for (int k = 0; k < kJetStride; ++k) scene.parameters[k].in_jet(seeded).v[k] = 1.0;
  const Trajectory<Jet> jet = Simulated(seeded);
  const Trajectory<double> value = Simulated(scene.model);

  // central differences, one parameter at a time
  std::vector<std::vector<VecX<double>>> dq(kJetStride), dv(kJetStride);
  for (int k = 0; k < kJetStride; ++k) {
    Model<double> plus = scene.model, minus = scene.model;
    const double p = scene.parameters[k].in_double(plus);
    const double h = kRelativeStep * std::max(1.0, std::abs(p));
    scene.parameters[k].in_double(plus) = p + h;
    scene.parameters[k].in_double(minus) = p - h;
    const Trajectory<double> up = Simulated(plus), down = Simulated(minus);
    ASSERT_EQ(up.q.size(), down.q.size());
    for (size_t t = 0; t < up.q.size(); ++t) {
      dq[k].push_back((up.q[t] - down.q[t]) / (2 * h));
      dv[k].push_back((up.v[t] - down.v[t]) / (2 * h));
    }
  }
  Compare(jet.q, value.q, dq, scene, kValueTolerance, "q");
  Compare(jet.v, value.v, dv, scene, kValueTolerance, "v");

  // the run went somewhere: the state moved, and every seeded field changed the final state
  EXPECT_GT((value.q.back() - value.q.front()).cwiseAbs().maxCoeff(), 0.05);
  for (int k = 0; k < kJetStride; ++k) {
    double largest = 0.0;
    for (int i = 0; i < jet.q.back().size(); ++i) largest = std::max(largest, std::abs(jet.q.back()[i].v[k]));
    EXPECT_GT(largest, 1e-3) << "d q / d " << scene.parameters[k].name;
  }
}

std::string CombinationName(const ::testing::TestParamInfo<Combination>& info) {
  const auto [kind, integrator, stabilization] = info.param;
  const char* scenes[] = {"Pendulum", "FourBar", "SliderOscillator"};
  const char* integrators[] = {"Euler", "SymplecticEuler", "Rk4", "Rk45"};
  const char* stabilizations[] = {"None", "Baumgarte", "Projection"};
  return std::string(scenes[static_cast<int>(kind)]) + "_" + integrators[static_cast<int>(integrator)] + "_" +
         stabilizations[static_cast<int>(stabilization)];
}

INSTANTIATE_TEST_SUITE_P(
    AllIntegratorsAndStabilizations, JetSimulation,
    ::testing::Combine(::testing::Values(SceneKind::kPendulum, SceneKind::kFourBar, SceneKind::kSliderOscillator),
                       ::testing::Values(Integrator::kEuler, Integrator::kSymplecticEuler, Integrator::kRk4,
                                         Integrator::kRk45),
                       ::testing::Values(Stabilization::kNone, Stabilization::kBaumgarte, Stabilization::kProjection)),
    CombinationName);

}  // namespace
}  // namespace tether
