// Contact between shapes (unilateral_events.h; the gaps themselves: contact_gaps_test.cc): the scene's shapes and
// pair rules as the contract states them, and contact dynamics against exact motions: a ball's bounces (times,
// speeds, heights), Newton's law between two balls, boxes dropped flat on a floor and on a box that come to rest
// on their faces, a plank resting across a beam on its crossed edges, no energy gained at any impact, Coulomb
// friction, time stepping, and Jet and adjoint gradients across impacts against the closed form and central
// differences.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "contact_scenes.h"
#include "gradient_checks.h"
#include "test_files.h"
#include "tether/autodiff/adjoint.h"
#include "tether/autodiff/residuals.h"
#include "tether/dynamics/constraints/contact_geometry.h"
#include "tether/dynamics/effects/effects.h"
#include "tether/dynamics/integration/stepper.h"
#include "tether/dynamics/io/scene_reader.h"
#include "tether/dynamics/model/configuration_space.h"

namespace tether {
namespace {

using nlohmann::json;

constexpr double kG = 9.81;

// A ball of radius 0.1 (a particle with a sphere, restitution e) dropped from h0 above a floor.
json Ball(double e, double h0, double duration, double step = 1e-3) {
  return {{"dimension", 3},
          {"bodies", {Particle("ball", {0.0, 0.0, 0.1 + h0})}},
          {"shapes",
           {{{"name", "ball_surface"}, {"body", "ball"}, {"type", "sphere"}, {"radius", 0.1}, {"restitution", e}},
            {{"name", "floor"}, {"body", "world"}, {"type", "plane"}}}},
          {"effects", {{{"type", "gravity"}, {"acceleration", {0.0, 0.0, -kG}}}}},
          {"simulation", {{"integrator", "rk4"}, {"step", step}, {"duration", duration}}}};
}

std::vector<RunEvent> Impacts(const RunReport& report) {
  std::vector<RunEvent> out;
  for (const RunEvent& e : report.events) {
    if (e.kind == "impact") out.push_back(e);
  }
  return out;
}

// ---------------------------------------------------------------------------------------------------------------
// the scene file

TEST(ContactScenes, ShapesAreReadWithTheirDefaultsLabelsAndParameters) {
  json scene = Ball(0.5, 1.0, 0.1);
  scene["contact"] = {{"friction", 0.4}, {"restitution", 0.2}};
  scene["shapes"].push_back({{"body", "ball"}, {"type", "capsule"}, {"radius", 0.05}, {"length", 0.3}});
  const Scene parsed = ParseScene(scene, "contact.json");
  const Model<double>& model = parsed.model;
  ASSERT_EQ(model.shapes.size(), 3u);
  EXPECT_EQ(model.shapes[2].label, "ball#1");  // its body's second shape
  const ContactGeometry geometry = BuildContactGeometry(model);
  ASSERT_EQ(geometry.pairs.size(), 2u);  // two shapes of one body never touch each other
  EXPECT_EQ(geometry.pairs[0].label, "ball_surface|floor");
  EXPECT_EQ(geometry.pairs[1].label, "floor|ball#1");
  EXPECT_EQ(PairRestitution(model, geometry.pairs[0].a, geometry.pairs[0].b), 0.5);  // the larger: the ball's own
  EXPECT_EQ(PairFriction(model, geometry.pairs[0].a, geometry.pairs[0].b), 0.4);     // neither gives one: the default
  EXPECT_EQ(PairRestitution(model, geometry.pairs[1].a, geometry.pairs[1].b), 0.2);
  for (const char* pointer :
       {"/shapes/0/radius", "/shapes/0/restitution", "/shapes/2/length", "/contact/friction", "/contact/restitution"}) {
    EXPECT_NE(parsed.numbers.Find(pointer), nullptr) << pointer;
  }
  EXPECT_EQ(geometry.features.size(), 3u);  // the sphere's centre and the capsule's two cap centres
}

TEST(ContactScenes, ThePairRulesLeaveOutJoinedExcludedAndUntouchableShapes) {
  json scene = {{"dimension", 3},
                {"bodies", {Particle("a", {0.0, 0.0, 1.0}), Particle("b", {0.0, 0.0, 2.0}), Particle("c", {1, 0, 1})}},
                {"constraints", {{{"type", "distance"}, {"bodies", {"a", "b"}}}}},
                {"shapes",
                 {{{"body", "a"}, {"type", "sphere"}, {"radius", 0.1}},
                  {{"body", "b"}, {"type", "sphere"}, {"radius", 0.1}},
                  {{"body", "c"}, {"type", "sphere"}, {"radius", 0.1}},
                  {{"body", "world"}, {"type", "plane"}},
                  {{"body", "world"}, {"type", "sphere"}, {"radius", 0.1}},
                  {{"body", "c"}, {"type", "box"}, {"size", {0.1, 0.1, 0.1}}, {"contact", false}}}},
                {"contact", {{"exclude", json::array({json::array({"c", "world"})})}}}};
  std::vector<std::string> labels;
  for (const ContactPair& pair : BuildContactGeometry(Parse(scene)).pairs) labels.push_back(pair.label);
  // a-b joined, c-world excluded, two world shapes never, the drawn box never
  EXPECT_EQ(labels, (std::vector<std::string>{"a#0|c#0", "a#0|world#0", "a#0|world#1", "b#0|c#0", "b#0|world#0",
                                              "b#0|world#1"}));
}

TEST(ContactScenes, BadShapesAreRefusedNamingThePointer) {
  struct Case {
    const char* pointer;
    std::function<void(json*)> change;
  };
  const std::vector<Case> cases = {
      {"/shapes/0/radius", [](json* s) { (*s)["shapes"][0]["radius"] = -0.1; }},
      {"/shapes/0: missing required key 'radius'", [](json* s) { (*s)["shapes"][0].erase("radius"); }},
      {"/shapes/0/restitution", [](json* s) { (*s)["shapes"][0]["restitution"] = 1.5; }},
      {"/shapes/1/friction", [](json* s) { (*s)["shapes"][1]["friction"] = -0.2; }},
      {"/shapes/0/body", [](json* s) { (*s)["shapes"][0]["body"] = "nobody"; }},
      {"/shapes/0/type", [](json* s) { (*s)["shapes"][0]["type"] = "torus"; }},
      {"/shapes/0/size",
       [](json* s) {
         (*s)["shapes"][0] = {{"body", "ball"}, {"type", "box"}, {"size", {0.1, 0.2}}};
       }},
      {"/shapes/0/size/1",
       [](json* s) {
         (*s)["shapes"][0] = {{"body", "ball"}, {"type", "box"}, {"size", {1, 0, 1}}};
       }},
      {"/shapes/0/length", [](json* s) { (*s)["shapes"][0]["length"] = 0.2; }},  // a sphere has none
      {"/shapes/1/radius", [](json* s) { (*s)["shapes"][1]["radius"] = 0.2; }},  // nor has a plane
      {"/shapes/0/angle", [](json* s) { (*s)["shapes"][0]["angle"] = 0.2; }},    // 3D: an orientation
      {"/shapes/0/orientation",
       [](json* s) {
         (*s)["shapes"][0]["orientation"] = {2.0, 0.0, 0.0, 0.0};
       }},
      {"/shapes/0/contact", [](json* s) { (*s)["shapes"][0]["contact"] = 1; }},
      {"/shapes/0/name", [](json* s) { (*s)["shapes"][0]["name"] = "ball"; }},  // a body's name
      {"/contact/exclude/0", [](json* s) { (*s)["contact"]["exclude"] = json::array({json::array({"ball"})}); }},
      {"/contact/exclude/0/1",
       [](json* s) {
         (*s)["contact"]["exclude"] = json::array({json::array({"ball", "nobody"})});
       }},
      {"/contact/restitution",
       [](json* s) {
         (*s)["contact"] = {{"restitution", 2.0}};
       }},
      {"/simulation/contact", [](json* s) { (*s)["simulation"]["contact"] = "soft"; }},
  };
  for (const Case& c : cases) {
    json scene = Ball(0.5, 1.0, 0.1);
    c.change(&scene);
    try {
      Parse(scene);
      ADD_FAILURE() << c.pointer << " was accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(std::string("contact.json: ") + c.pointer), std::string::npos) << e.what();
    }
  }
}

// ---------------------------------------------------------------------------------------------------------------
// frictionless contact dynamics

TEST(ContactDynamics, ABallBouncesAtTheExactTimesAndSpeeds) {
  const double e = 0.8, h0 = 1.0;
  double z_end = NAN;
  const RunReport report =
      Simulate<double>(Parse(Ball(e, h0, 2.0)), RunOptions{}, [&](const Sample<double>& s) { z_end = s.q[2]; });
  const std::vector<RunEvent> impacts = Impacts(report);
  ASSERT_EQ(impacts.size(), 3u);
  const double t1 = std::sqrt(2 * h0 / kG), v0 = kG * t1;
  double t = t1, v = v0;
  for (const RunEvent& impact : impacts) {
    EXPECT_EQ(impact.constraint, "ball_surface|floor");
    EXPECT_NEAR(impact.t, t, 1e-12);
    EXPECT_NEAR(impact.speed_before, -v, 1e-11);
    EXPECT_NEAR(impact.speed_after, e * v, 1e-11);
    v *= e;
    t += 2 * v / kG;
  }
  const double tau = 2.0 - (t - 2 * v / kG);  // in the fourth flight
  EXPECT_NEAR(z_end, 0.1 + v * tau - kG * tau * tau / 2, 1e-12);
}

TEST(ContactDynamics, TwoBallsMeetByNewtonsLawKeepingMomentum) {
  // head-on, 2 m/s and -1 m/s along x, no gravity: v_a' = (m_a v_a + m_b v_b - m_b e (v_a - v_b)) / (m_a + m_b)
  json scene = {
      {"dimension", 3},
      {"bodies", {Particle("a", {0.0, 0.0, 0.0}, {2.0, 0.0, 0.0}), Particle("b", {1.0, 0.0, 0.0}, {-1, 0, 0})}},
      {"shapes",
       {{{"body", "a"}, {"type", "sphere"}, {"radius", 0.2}, {"restitution", 0.5}},
        {{"body", "b"}, {"type", "sphere"}, {"radius", 0.1}}}},
      {"simulation", {{"step", 1e-3}, {"duration", 0.5}}}};
  scene["bodies"][1]["mass"] = 3.0;
  Vec3<double> va, vb;
  const RunReport report = Simulate<double>(Parse(scene), RunOptions{}, [&](const Sample<double>& s) {
    va = s.v.segment<3>(0);
    vb = s.v.segment<3>(3);
  });
  ASSERT_EQ(Impacts(report).size(), 1u);
  EXPECT_NEAR(Impacts(report)[0].t, 0.7 / 3.0, 1e-12);
  EXPECT_NEAR(va.x(), (2.0 - 3.0 - 3.0 * 0.5 * 3.0) / 4.0, 1e-12);
  EXPECT_NEAR(vb.x(), (2.0 - 3.0 + 0.5 * 3.0) / 4.0, 1e-12);
}

// the total energy of a conservative scene (gravity only) at each sample
std::vector<double> Energies(const Model<double>& model, RunReport* report) {
  std::vector<double> energy;
  *report = Simulate<double>(model, RunOptions{}, [&](const Sample<double>& s) { energy.push_back(s.energy); });
  return energy;
}

TEST(ContactDynamics, ABoxDroppedFlatComesToRestOnItsFace) {
  json scene = {
      {"dimension", 3},
      {"bodies",
       {{{"name", "box"},
         {"type", "rigid"},
         {"mass", 1.0},
         {"inertia", {0.00667, 0.00667, 0.00667}},
         {"position", {0.0, 0.0, 0.25}}}}},
      {"shapes",
       {{{"body", "box"}, {"type", "box"}, {"size", {0.2, 0.2, 0.2}}}, {{"body", "world"}, {"type", "plane"}}}},
      {"effects", {{{"type", "gravity"}, {"acceleration", {0.0, 0.0, -kG}}}}},
      {"simulation", {{"step", 1e-3}, {"duration", 0.5}}}};
  double z = NAN;
  Vec4<double> orientation;
  const RunReport report = Simulate<double>(Parse(scene), RunOptions{}, [&](const Sample<double>& s) {
    z = s.q[2];
    orientation = s.q.segment<4>(3);
  });
  ASSERT_EQ(Impacts(report).size(), 4u);  // the four lower corners at once
  EXPECT_NEAR(Impacts(report)[0].t, std::sqrt(2 * 0.15 / kG), 1e-12);
  EXPECT_NEAR(z, 0.1, 1e-12);
  EXPECT_NEAR(std::abs(orientation[0]), 1.0, 1e-12);
}

// Runs the scene (restitution e) and checks that it has at least `impacts` impacts and that its energy never rises
// above the start's by more than 1e-6 of it; returns the energies.
std::vector<double> EnergyNeverRises(const json& scene, size_t impacts, double e) {
  RunReport report;
  const std::vector<double> energy = Energies(Parse(scene), &report);
  EXPECT_GE(Impacts(report).size(), impacts) << "e = " << e;
  const double highest = *std::max_element(energy.begin(), energy.end());
  EXPECT_LT(highest - energy[0], 1e-6 * std::abs(energy[0])) << "e = " << e;
  return energy;
}

TEST(ContactDynamics, NoImpactGainsEnergy) {
  // a tumbling capsule and a box dropped on the floor with e = 1 and e = 0.5: the energy never rises
  for (const double e : {1.0, 0.5}) {
    json scene = {{"dimension", 3},
                  {"bodies",
                   {Rigid3d("rod", {0.0, 0.0, 0.6}, {0.9, 0.3, 0.3, 0.1}, {3, -2, 1}),
                    Rigid3d("box", {2.0, 0.0, 0.7}, {0.8, -0.1, 0.5, 0.3162277660168379}, {-1, 2, 2})}},
                  {"shapes",
                   {{{"body", "rod"}, {"type", "capsule"}, {"radius", 0.05}, {"length", 0.5}},
                    {{"body", "box"}, {"type", "box"}, {"size", {0.2, 0.3, 0.4}}},
                    {{"body", "world"}, {"type", "plane"}, {"restitution", e}}}},
                  {"contact", {{"exclude", json::array({json::array({"rod", "box"})})}}},
                  {"effects", {{{"type", "gravity"}, {"acceleration", {0.0, 0.0, -kG}}}}},
                  {"simulation", {{"step", 1e-3}, {"duration", 1.5}}}};
    const std::vector<double> energy = EnergyNeverRises(scene, 2, e);
    if (e == 1.0) EXPECT_NEAR(energy.back(), energy[0], 1e-6 * std::abs(energy[0]));
  }
}

// A world box (a pedestal, a beam) with its top face at z = top, and the scene's other parts.
json OnABox(const json& bodies, const json& shapes, const std::vector<double>& size, double top, double duration,
            const std::string& mode) {
  json all_shapes = shapes;
  all_shapes.push_back({{"name", "pedestal"},
                        {"body", "world"},
                        {"type", "box"},
                        {"size", size},
                        {"position", {0.0, 0.0, top - size[2] / 2}}});
  return {{"dimension", 3},
          {"bodies", bodies},
          {"shapes", all_shapes},
          {"effects", {{{"type", "gravity"}, {"acceleration", {0.0, 0.0, -kG}}}}},
          {"simulation",
           {{"integrator", mode == "events" ? "rk4" : "symplectic_euler"},
            {"step", 1e-3},
            {"duration", duration},
            {"contact", mode}}},
          {"stabilization", {{"alpha", 100.0}, {"beta", 2500.0}}}};
}

TEST(ContactDynamics, ABoxAndACapsuleTumblingOntoABoxGainNoEnergy) {
  // a box and a capsule spinning as they fall onto a pedestal, then onto each other and the pedestal's edges:
  // corners against faces, crossed edges, a cap against a face; the energy never rises
  for (const double e : {1.0, 0.5}) {
    const json scene =
        OnABox(json::array({Rigid3d("rod", {0.1, 0.0, 0.8}, {0.9, 0.3, 0.3, 0.1}, {3, -2, 1}),
                            Rigid3d("box", {-0.1, 0.1, 1.5}, {0.8, -0.1, 0.5, 0.3162277660168379}, {-1, 2, 2})}),
               json::array({{{"body", "rod"}, {"type", "capsule"}, {"radius", 0.05}, {"length", 0.5}},
                            {{"body", "box"}, {"type", "box"}, {"size", {0.2, 0.3, 0.4}}, {"restitution", e}}}),
               {0.8, 0.6, 0.4}, 0.4, 1.0, "events");
    EnergyNeverRises(scene, 3, e);
  }
}

TEST(ContactDynamics, ABoxDroppedFlatOnABoxComesToRestOnItsFace) {
  // a 0.2 m cube dropped 5 cm onto a pedestal whose top is at 0.4 m: its four lower corners land at once, 1 m/s
  const json scene = OnABox(json::array({Rigid3d("box", {0.05, -0.03, 0.55}, {1, 0, 0, 0})}),
                            json::array({{{"body", "box"}, {"type", "box"}, {"size", {0.2, 0.2, 0.2}}}}),
                            {0.6, 0.6, 0.4}, 0.4, 0.6, "events");
  json level = scene;
  level["bodies"][0]["velocity"] = {0.0, 0.0, 0.0};
  level["bodies"][0]["angular_velocity"] = {0.0, 0.0, 0.0};
  VecX<double> q, v;
  const RunReport report = Simulate<double>(Parse(level), RunOptions{}, [&](const Sample<double>& s) {
    q = s.q;
    v = s.v;
  });
  ASSERT_EQ(Impacts(report).size(), 4u);
  EXPECT_NEAR(Impacts(report)[0].t, std::sqrt(2 * 0.05 / kG), 1e-9);
  EXPECT_NEAR(q[2], 0.5, 1e-9);
  EXPECT_LT(v.norm(), 1e-9);
}

TEST(ContactTimeStepping, APlankLaidAcrossABeamRestsOnTheEdgesItCrosses) {
  // a plank along x dropped 1 cm across a beam along y: none of their corners is over the other's face, so only
  // the four crossings of their edges hold it (a layer of a Jenga tower); it comes to rest level on the beam,
  // and so does a capsule laid across it
  const json plank = {{"name", "plank"},
                      {"type", "rigid"},
                      {"mass", 1.0},
                      {"inertia", {0.001, 0.08, 0.08}},
                      {"position", {0.02, -0.01, 0.3 + 0.025 + 0.01}}};
  const json rod = {{"name", "rod"},
                    {"type", "rigid"},
                    {"mass", 1.0},
                    {"inertia", {0.001, 0.08, 0.08}},
                    {"position", {0.01, 0.02, 0.3 + 0.05 + 0.01}}};
  for (const std::string mode : {"stepping", "events"}) {
    for (const bool capsule : {false, true}) {
      const json shape = capsule ? json{{"body", "rod"}, {"type", "capsule"}, {"radius", 0.05}, {"length", 1.0}}
                                 : json{{"body", "plank"}, {"type", "box"}, {"size", {1.0, 0.1, 0.05}}};
      const json scene =
          OnABox(json::array({capsule ? rod : plank}), json::array({shape}), {0.1, 1.0, 0.3}, 0.3, 0.5, mode);
      VecX<double> q;
      Simulate<double>(Parse(scene), RunOptions{}, [&](const Sample<double>& s) { q = s.q; });
      EXPECT_NEAR(q[2], capsule ? 0.35 : 0.325, 1e-7) << mode << (capsule ? " capsule" : " plank");
      EXPECT_NEAR(std::abs(q[3]), 1.0, 1e-9) << mode << (capsule ? " capsule" : " plank");  // level
    }
  }
}

// ---------------------------------------------------------------------------------------------------------------
// Coulomb friction

// A cube (0.2 m, 1 kg) resting on a slope of `degrees` in 3D (or a square on a line in 2D), both with friction mu.
json Incline(int dimension, double mu, double degrees, double duration = 1.0) {
  const double th = degrees * M_PI / 180.0;
  json body = {{"name", "box"}, {"type", "rigid"}, {"mass", 1.0}};
  json slope = {{"name", "ramp"}, {"body", "world"}, {"type", "plane"}, {"friction", mu}};
  if (dimension == 3) {
    const std::vector<double> q = {std::cos(th / 2), 0.0, -std::sin(th / 2), 0.0};  // -th about y
    body["inertia"] = {0.08 / 12, 0.08 / 12, 0.08 / 12};
    body["position"] = {-0.1 * std::sin(th), 0.0, 0.1 * std::cos(th)};
    body["orientation"] = q;
    slope["orientation"] = q;
  } else {
    body["inertia"] = 0.08 / 12;
    body["position"] = {-0.1 * std::sin(th), 0.1 * std::cos(th)};
    body["angle"] = th;
    slope["angle"] = th;
  }
  const std::vector<double> size(dimension, 0.2);
  return {{"dimension", dimension},
          {"bodies", {body}},
          {"shapes", {{{"name", "block"}, {"body", "box"}, {"type", "box"}, {"size", size}, {"friction", mu}}, slope}},
          {"effects", {{{"type", "gravity"}, {"acceleration", dimension == 3 ? json{0.0, 0.0, -kG} : json{0.0, -kG}}}}},
          {"simulation", {{"integrator", "rk4"}, {"step", 1e-3}, {"duration", duration}}}};
}

TEST(ContactFriction, ABoxOnASlopeSlidesAtCoulombsAccelerationOrSticksWithoutCreep) {
  const double th = 30.0 * M_PI / 180.0;
  for (const int dimension : {2, 3}) {
    for (const double mu : {0.3, 0.6}) {  // tan 30 degrees = 0.577
      const double a = mu < std::tan(th) ? kG * (std::sin(th) - mu * std::cos(th)) : 0.0;
      const Model<double> model = Parse(Incline(dimension, mu, 30.0));
      const int d = dimension;
      const Vec3<double> down(-std::cos(th), d == 3 ? 0.0 : -std::sin(th), d == 3 ? -std::sin(th) : 0.0);
      const Vec3<double> normal(-std::sin(th), d == 3 ? 0.0 : std::cos(th), d == 3 ? std::cos(th) : 0.0);
      Vec3<double> start = Vec3<double>::Zero();
      double worst_along = 0.0, worst_off = 0.0;
      Simulate<double>(model, RunOptions{}, [&](const Sample<double>& s) {
        Vec3<double> x = Vec3<double>::Zero();
        x.head(d) = s.q.head(d);
        if (s.t == 0.0) start = x;
        worst_along = std::max(worst_along, std::abs((x - start).dot(down) - a * s.t * s.t / 2));
        worst_off = std::max(worst_off, std::abs((x - start).dot(normal)));
      });
      EXPECT_LT(worst_along, a > 0 ? 1e-9 : 1e-12) << "dimension " << d << ", mu " << mu;
      EXPECT_LT(worst_off, 1e-12) << "dimension " << d << ", mu " << mu;
    }
  }
}

TEST(ContactFriction, AStuckBoxSlipsTheInstantThePushReachesTheCone) {
  // a ramp force F = 10 t at the centre of a cube on the floor (mu = 0.3): it sticks until 10 t = mu m g, then
  // x = 5/3 (t - t_s)^3 (a = 10 t - mu g from t_s = mu g / 10)
  json scene = Incline(3, 0.3, 0.0, 0.6);
  scene["effects"].push_back({{"type", "force"},
                              {"body", "box"},
                              {"schedule", {{"times", {0.0, 1.0}}, {"values", {{0.0, 0.0, 0.0}, {10.0, 0.0, 0.0}}}}}});
  double x = NAN, before = 0.0;
  const double ts = 0.3 * kG / 10.0;
  const RunReport report = Simulate<double>(Parse(scene), RunOptions{}, [&](const Sample<double>& s) {
    x = s.q[0];
    if (s.t < ts) before = std::max(before, std::abs(x));
  });
  std::vector<RunEvent> slips;
  for (const RunEvent& e : report.events) {
    if (e.kind == "slip") slips.push_back(e);
  }
  ASSERT_EQ(slips.size(), 1u);
  EXPECT_EQ(slips[0].constraint, "block|ramp");
  EXPECT_NEAR(slips[0].t, ts, 1e-10);
  EXPECT_LT(before, 1e-12);
  EXPECT_NEAR(x, 5.0 / 3.0 * std::pow(0.6 - ts, 3), 1e-10);
}

// A ball (sphere in 3D, disc in 2D) launched sliding at v0 on a floor with friction mu.
json Launched(int dimension, double mu, double v0, double inertia) {
  json ball = {{"name", "ball"}, {"type", "rigid"}, {"mass", 1.0}};
  if (dimension == 3) {
    ball["inertia"] = {inertia, inertia, inertia};
    ball["position"] = {0.0, 0.0, 0.1};
    ball["velocity"] = {v0, 0.0, 0.0};
  } else {
    ball["inertia"] = inertia;
    ball["position"] = {0.0, 0.1};
    ball["velocity"] = {v0, 0.0};
  }
  return {{"dimension", dimension},
          {"bodies", {ball}},
          {"shapes",
           {{{"name", "surface"}, {"body", "ball"}, {"type", "sphere"}, {"radius", 0.1}, {"friction", mu}},
            {{"name", "floor"}, {"body", "world"}, {"type", "plane"}}}},
          {"effects", {{{"type", "gravity"}, {"acceleration", dimension == 3 ? json{0.0, 0.0, -kG} : json{0.0, -kG}}}}},
          {"simulation", {{"integrator", "rk4"}, {"step", 1e-3}, {"duration", 1.0}}}};
}

TEST(ContactFriction, ASlidingBallRollsFromTheClosedFormTime) {
  // v' = -mu g, w' = mu g m R / I: the slip v - w R stops at t_s = v0 / (mu g (1 + m R^2 / I)), then it rolls
  const double mu = 0.3, v0 = 2.0, R = 0.1;
  for (const int dimension : {2, 3}) {
    const double inertia = dimension == 3 ? 0.4 * R * R : 0.5 * R * R;  // a solid sphere, a disc
    const double ts = v0 / (mu * kG * (1 + R * R / inertia)), vs = v0 - mu * kG * ts;
    double x = NAN, vx = NAN, height = 0.0;
    const RunReport report =
        Simulate<double>(Parse(Launched(dimension, mu, v0, inertia)), RunOptions{}, [&](const Sample<double>& s) {
          x = s.q[0];
          vx = s.v[0];
          height = std::max(height, std::abs(s.q[dimension - 1] - R));
        });
    ASSERT_EQ(report.events.size(), 1u) << dimension;
    EXPECT_EQ(report.events[0].kind, "stick");
    EXPECT_NEAR(report.events[0].t, ts, 1e-10) << dimension;
    const Vec3<double> up = dimension == 3 ? Vec3<double>::UnitZ() : Vec3<double>::UnitY();  // under the ball
    EXPECT_LT((report.events[0].point - (v0 * ts - mu * kG * ts * ts / 2) * Vec3<double>::UnitX()).norm(), 1e-10);
    EXPECT_LT((report.events[0].normal - up).norm(), 1e-12) << dimension;
    EXPECT_EQ(report.events[0].impulse, 0.0);
    EXPECT_NEAR(vx, vs, 1e-10) << dimension;
    EXPECT_NEAR(x, v0 * ts - mu * kG * ts * ts / 2 + vs * (1.0 - ts), 1e-10) << dimension;
    EXPECT_LT(height, 1e-12) << dimension;
  }
}

TEST(ContactFriction, JetsAndTheAdjointThroughTheStopOfASlipMatchTheClosedFormAndCentralDifferences) {
  // x(1) = v0 t_s - mu g t_s^2 / 2 + (5/7) v0 (1 - t_s), t_s = 2 v0 / (7 mu g): d/dmu and d/dv0
  const testing::TempFolder folder;
  const double mu = 0.3, v0 = 2.0;
  const Scene scene = ParseScene(Launched(3, mu, v0, 0.004), "ball.json");
  const ParameterSet parameters(scene, {"/shapes/0/friction", "/bodies/0/velocity/0"});
  const Observations observations = ReadObservations(folder.Write("ball.csv", "t,ball.x\n1.0,0.0\n"), scene.model);
  const LossGradient jet = JetLossGradient(scene.model, parameters, observations);
  const auto x_at_1 = [](double m, double v) {
    const double ts = 2 * v / (7 * m * kG);
    return v * ts - m * kG * ts * ts / 2 + 5.0 / 7.0 * v * (1 - ts);
  };
  const double x = x_at_1(mu, v0), h = 1e-6;
  EXPECT_NEAR(jet.gradient[0], x * (x_at_1(mu + h, v0) - x_at_1(mu - h, v0)) / (2 * h), 1e-7);
  EXPECT_NEAR(jet.gradient[1], x * (x_at_1(mu, v0 + h) - x_at_1(mu, v0 - h)) / (2 * h), 1e-7);
  testing::ExpectGradientsAgree(scene.model, parameters, observations);
}

TEST(ContactFriction, TheAdjointThroughABoxSlidingOnASlopeMatchesJetsAndCentralDifferences) {
  // a cube sliding down a 30-degree slope on its four corners (redundant sliding rows: the regularized solve) for
  // 0.5 s: its position's derivatives with respect to mu (the cube's: the pair takes the larger, so the slope's is
  // 0) and to gravity
  const testing::TempFolder folder;
  json slope = Incline(3, 0.3, 30.0, 0.5);
  slope["shapes"][1]["friction"] = 0.0;
  const Scene scene = ParseScene(slope, "slope.json");
  const ParameterSet parameters(scene, {"/shapes/0/friction", "/effects/0/acceleration/2"});
  const Observations observations =
      ReadObservations(folder.Write("box.csv", "t,box.x,box.z\n0.5,0.0,0.0\n"), scene.model);
  const LossGradient jet = JetLossGradient(scene.model, parameters, observations);
  const LossGradient adjoint = AdjointLossGradient(scene.model, parameters, observations);
  const LossGradient central = CentralDifferenceLossGradient(scene.model, parameters, observations);
  for (size_t i = 0; i < jet.gradient.size(); ++i) {
    EXPECT_GT(std::abs(jet.gradient[i]), 1e-3) << i;
    EXPECT_NEAR(adjoint.gradient[i], jet.gradient[i], 1e-9 * std::abs(jet.gradient[i])) << i;
    EXPECT_NEAR(jet.gradient[i], central.gradient[i], 1e-6 * std::abs(central.gradient[i])) << i;
  }
}

// A uniform rod (1 m, 1 kg) at 30 degrees, its lower end (radius 0.01) on the floor and leading as it slides at
// 1 m/s, with friction mu.
constexpr double kRodAngle = M_PI / 6, kRodRadius = 0.01;
json SlidingRod(double mu, double duration) {
  return {{"dimension", 2},
          {"bodies",
           {{{"name", "rod"},
             {"type", "rigid"},
             {"mass", 1.0},
             {"inertia", 1.0 / 12},
             {"position", {0.0, 0.5 * std::sin(kRodAngle) + kRodRadius}},
             {"angle", kRodAngle},
             {"velocity", {-1.0, 0.0}}}}},
          {"shapes",
           {{{"name", "stick"},
             {"body", "rod"},
             {"type", "capsule"},
             {"radius", kRodRadius},
             {"length", 1.0},
             {"friction", mu}},
            {{"name", "floor"}, {"body", "world"}, {"type", "plane"}}}},
          {"effects", {{{"type", "gravity"}, {"acceleration", {0.0, -kG}}}}},
          {"simulation", {{"step", 1e-3}, {"duration", duration}}}};
}

TEST(ContactFriction, PainlevesParadoxIsReportedNamingTheContactAndTheTime) {
  // with I = m l^2 / 3 (l half its length) the normal acceleration's coefficient of N is 1 + 3 cos(th) (cos(th) -
  // mu sin(th)) over m, negative for mu > 2.5 (Painleve's paradox); mu = 1 slides on
  for (const double mu : {3.0, 1.0}) {
    const json scene = SlidingRod(mu, 0.05);
    if (mu < 2.5) {
      EXPECT_NO_THROW(Simulate<double>(Parse(scene), RunOptions{}, [](const Sample<double>&) {}));
      continue;
    }
    try {
      Simulate<double>(Parse(scene), RunOptions{}, [](const Sample<double>&) {});
      ADD_FAILURE() << "Painleve's paradox passed silently";
    } catch (const SimulationDiverged& e) {
      EXPECT_NE(std::string(e.what()).find("Painleve's paradox at the contact stick|floor"), std::string::npos)
          << e.what();
      EXPECT_NE(std::string(e.what()).find("t = 0 s"), std::string::npos) << e.what();
    }
  }
}

// ---------------------------------------------------------------------------------------------------------------
// time stepping (unilateral_stepping.cc)

json Stepping(json scene, double step) {
  scene["simulation"]["contact"] = "stepping";
  scene["simulation"]["step"] = step;
  return scene;
}

TEST(ContactTimeStepping, ABallWithoutRestitutionLandsOnTheFloorAndTheGainsCloseWhatItOverlaps) {
  // e = 0, h = 5 ms: the speculative impulse one step before the floor leaves it to close the gap over the next
  // step, whose gravity overlaps it by h^2 g / 2 at most; the gains close that (k = h beta / (1 + h alpha): the gap
  // shrinks by 1 - h k / 2 a step), without gains it stays
  const double h = 5e-3, t1 = std::sqrt(2 * 0.5 / kG);
  for (const auto& [alpha, beta] : {std::pair{0.0, 0.0}, std::pair{100.0, 2500.0}}) {
    json scene = Stepping(Ball(0.0, 0.5, 1.0), h);
    scene["stabilization"] = {{"alpha", alpha}, {"beta", beta}};
    double deepest = 0.0, z = NAN;
    const RunReport report = Simulate<double>(Parse(scene), RunOptions{}, [&](const Sample<double>& s) {
      z = s.q[2];
      deepest = std::min(deepest, z - 0.1);
    });
    ASSERT_EQ(Impacts(report).size(), 1u);
    EXPECT_NEAR(Impacts(report)[0].t, t1, h);
    EXPECT_GT(deepest, -h * h * kG / 2 - 1e-15);
    if (beta > 0.0) EXPECT_NEAR(z, 0.1, 1e-12);
  }
}

TEST(ContactTimeStepping, ABouncingBallKeepsItsRestitutionToFirstOrder) {
  // e = 0.8 from 1 m: Newton's law at the step where it overlaps; the rebound's apex e^2 h0 to a few steps' fall
  for (const double h : {1e-3, 5e-4}) {
    double apex = 0.0;
    bool rising = false;
    const RunReport report =
        Simulate<double>(Parse(Stepping(Ball(0.8, 1.0, 1.2), h)), RunOptions{}, [&](const Sample<double>& s) {
          rising = rising || s.v[2] > 0.0;
          if (rising) apex = std::max(apex, s.q[2] - 0.1);
        });
    ASSERT_GE(Impacts(report).size(), 1u);
    // Newton's law, and the gains' push out of the overlap the step left (first order in h)
    EXPECT_NEAR(Impacts(report)[0].speed_after, -0.8 * Impacts(report)[0].speed_before,
                1e-4 * -Impacts(report)[0].speed_before);
    EXPECT_NEAR(apex, 0.64, 4.0 * h * std::sqrt(2 * kG)) << "h " << h;
  }
}

TEST(ContactTimeStepping, ABoxOnASlopeSticksWithoutCreepOrSlidesAtCoulombsAcceleration) {
  // four corners on the slope (dependent rows); the impulse moves q as rk4 moves it under a constant force, so a
  // sticking box stays where it is; a sliding one accelerates at g (sin - mu cos) to first order
  const double th = 30.0 * M_PI / 180.0;
  for (const int dimension : {2, 3}) {
    for (const double mu : {0.3, 0.6}) {
      const double a = mu < std::tan(th) ? kG * (std::sin(th) - mu * std::cos(th)) : 0.0;
      const int d = dimension;
      const Vec3<double> down(-std::cos(th), d == 3 ? 0.0 : -std::sin(th), d == 3 ? -std::sin(th) : 0.0);
      const Vec3<double> normal(-std::sin(th), d == 3 ? 0.0 : std::cos(th), d == 3 ? std::cos(th) : 0.0);
      Vec3<double> start = Vec3<double>::Zero();
      double worst_along = 0.0, worst_off = 0.0;
      const RunReport report = Simulate<double>(
          Parse(Stepping(Incline(dimension, mu, 30.0), 1e-3)), RunOptions{}, [&](const Sample<double>& s) {
            Vec3<double> x = Vec3<double>::Zero();
            x.head(d) = s.q.head(d);
            if (s.t == 0.0) start = x;
            if (s.t < 2e-3) return;  // the first step slides before it touches
            const double along = (x - start).dot(down);
            worst_along = std::max(worst_along, std::abs(along - a * s.t * s.t / 2));
            worst_off = std::max(worst_off, std::abs((x - start).dot(normal)));
          });
      // a sticking box moves by one step's slide, h^2 g sin(th) / 2, before it first touches, then by < 1 nm
      EXPECT_LT(worst_along, a > 0 ? 2e-3 * a : 1e-6 * kG * std::sin(th) / 2 + 1e-9)
          << "dimension " << d << ", mu " << mu;
      EXPECT_LT(worst_off, 1e-5) << "dimension " << d << ", mu " << mu;
      EXPECT_TRUE(report.warnings.empty()) << report.warnings.front();
    }
  }
}

TEST(ContactTimeStepping, ASideTheImpulsesDriveIntoItsSurfaceJoinsThem) {
  // no gravity: a plate (a sphere) at rest 0.5 mm above the floor, a ball of its mass landing on it at 3 m/s. The
  // landing's impulse sends the plate down at 1.5 m/s, 1.5 mm a step: its floor side, apart and at rest before the
  // impulses, joins them, and the plate ends the next step on the floor instead of 1 mm into it
  const json scene = {
      {"dimension", 3},
      {"bodies", {Particle("plate", {0.0, 0.0, 0.1005}), Particle("ball", {0.0, 0.0, 0.302}, {0.0, 0.0, -3.0})}},
      {"shapes",
       {{{"name", "plate_surface"}, {"body", "plate"}, {"type", "sphere"}, {"radius", 0.1}},
        {{"name", "ball_surface"}, {"body", "ball"}, {"type", "sphere"}, {"radius", 0.1}},
        {{"name", "floor"}, {"body", "world"}, {"type", "plane"}}}},
      {"simulation", {{"integrator", "rk4"}, {"step", 1e-3}, {"duration", 0.01}, {"contact", "stepping"}}}};
  double lowest = 1.0;
  const RunReport report = Simulate<double>(Parse(scene), RunOptions{},
                                            [&](const Sample<double>& s) { lowest = std::min(lowest, s.q[2] - 0.1); });
  EXPECT_GT(lowest, -1e-12);
  EXPECT_EQ(Impacts(report).size(), 2u);  // the ball on the plate, the plate on the floor
}

TEST(ContactTimeStepping, AnImpactPassedOnToARestingContactChangesTheVelocityOnly) {
  // a plate (a sphere) resting on the floor, a ball of its mass landing on it at 3 m/s: the floor's impulse stops
  // both, and all but the plate's weight over the step is the landing's, passed on through the plate. Moving the
  // configuration by the floor's impulse as by a force would lift the plate off the floor by w h 3 m/s (1.5 mm at
  // rk4's w = 1/2), by all the impulses the ball off the plate as much: the ball lands on the plate and stays (7.5 mm
  // above it at the start, so that the landing is a step's end, not the first step's)
  const double h = 1e-3;
  const json scene = {
      {"dimension", 3},
      {"bodies", {Particle("plate", {0.0, 0.0, 0.1}), Particle("ball", {0.0, 0.0, 0.3075}, {0.0, 0.0, -3.0})}},
      {"shapes",
       {{{"name", "plate_surface"}, {"body", "plate"}, {"type", "sphere"}, {"radius", 0.1}},
        {{"name", "ball_surface"}, {"body", "ball"}, {"type", "sphere"}, {"radius", 0.1}},
        {{"name", "floor"}, {"body", "world"}, {"type", "plane"}}}},
      {"effects", {{{"type", "gravity"}, {"acceleration", {0.0, 0.0, -kG}}}}},
      {"simulation", {{"integrator", "rk4"}, {"step", h}, {"duration", 0.05}, {"contact", "stepping"}}}};
  double plate = 0.0, ball = 0.0;  // the largest distances from the floor, and from the plate once landed
  Simulate<double>(Parse(scene), RunOptions{}, [&](const Sample<double>& s) {
    plate = std::max(plate, std::abs(s.q[2] - 0.1));
    if (s.v[5] > -1.0) ball = std::max(ball, std::abs(s.q[5] - s.q[2] - 0.2));
  });
  EXPECT_LT(plate, h * h * kG);  // a step's fall under gravity, at most
  EXPECT_LT(ball, h * h * kG);
}

TEST(ContactTimeStepping, ATiltedBoxDroppedOnTheFloorComesToRestFlat) {
  // h = 5 ms: each step's fall under gravity opens h^2 g = 0.25 mm under a resting box, which the impulses' force
  // part closes again; an edge left that far up must be free to come down, or the box rests tilted on the other
  const double half = 0.1, inertia = 2.0 * half * half / 3.0;
  const json scene = {
      {"dimension", 3},
      {"bodies",
       {{{"name", "box"},
         {"type", "rigid"},
         {"mass", 1.0},
         {"inertia", {inertia, inertia, inertia}},
         {"position", {0.0, 0.0, 0.5}},
         {"orientation", {std::cos(0.05), std::sin(0.05), 0.0, 0.0}}}}},
      {"shapes",
       {{{"name", "box_surface"}, {"body", "box"}, {"type", "box"}, {"size", {2 * half, 2 * half, 2 * half}}},
        {{"name", "floor"}, {"body", "world"}, {"type", "plane"}}}},
      {"effects", {{{"type", "gravity"}, {"acceleration", {0.0, 0.0, -kG}}}}},
      {"simulation", {{"integrator", "symplectic_euler"}, {"step", 5e-3}, {"duration", 2.0}, {"contact", "stepping"}}},
      {"stabilization", {{"alpha", 100.0}, {"beta", 2500.0}}}};
  VecX<double> q;
  Simulate<double>(Parse(scene), RunOptions{}, [&](const Sample<double>& s) { q = s.q; });
  EXPECT_NEAR(q[2], half, 1e-9);
  EXPECT_NEAR(std::abs(q[3]), 1.0, 1e-12);  // the unit quaternion's w: no tilt left
}

TEST(ContactTimeStepping, PainlevesRodSlidesOnWithoutAParadoxAtTheImpulseLevel) {
  // the rod of PainlevesParadoxIsReported (mu = 3, no consistent accelerations): impulses always have a solution
  const json scene = SlidingRod(3.0, 0.5);
  double lowest = 1.0;
  EXPECT_NO_THROW(Simulate<double>(Parse(Stepping(scene, 1e-3)), RunOptions{}, [&](const Sample<double>& s) {
    lowest = std::min(lowest, s.q[1] - 0.5 * std::sin(s.q[2]) - kRodRadius);
  }));
  EXPECT_GT(lowest, -3e-3);  // measured 2.0e-3: the leading end's overlap, which the default gains close
}

TEST(ContactTimeStepping, JetsAndTheAdjointThroughTheImpulsesMatchCentralDifferences) {
  // a ball without restitution landed and rested: the loss z(T)^2 / 2 against its radius (z = R once the gains have
  // closed the overlap: dz/dR = 1) and its drop height (0)
  const testing::TempFolder folder;
  const Scene scene = ParseScene(Stepping(Ball(0.0, 0.3, 0.8), 5e-3), "ball.json");
  const ParameterSet parameters(scene, {"/shapes/0/radius", "/bodies/0/position/2"});
  const Observations observations = ReadObservations(folder.Write("ball.csv", "t,ball.z\n0.8,0.0\n"), scene.model);
  const LossGradient central = CentralDifferenceLossGradient(scene.model, parameters, observations);
  EXPECT_NEAR(central.gradient[0], 0.1, 1e-7);
  EXPECT_NEAR(central.gradient[1], 0.0, 1e-7);
  const LossGradient jet = JetLossGradient(scene.model, parameters, observations);
  const LossGradient adjoint = AdjointLossGradient(scene.model, parameters, observations);
  for (size_t i = 0; i < central.gradient.size(); ++i) {
    // the impulses' derivatives, and those of their impacts' part, are the implicit function's
    EXPECT_NEAR(jet.gradient[i], central.gradient[i], 1e-8) << i;
    EXPECT_NEAR(adjoint.gradient[i], jet.gradient[i], 1e-9) << i;
  }
}

// ---------------------------------------------------------------------------------------------------------------
// gradients across an impact

TEST(ContactGradients, JetsAndTheAdjointAcrossABounceMatchTheClosedFormAndCentralDifferences) {
  // z(T) = R + e v0 tau - g tau^2 / 2, tau = T - t1 (contact.py's gradient-bounce)
  const testing::TempFolder folder;
  const double e = 0.8, h0 = 1.0, T = 0.7;
  const double t1 = std::sqrt(2 * h0 / kG), v0 = kG * t1, tau = T - t1;
  const Scene scene = ParseScene(Ball(e, h0, 1.0), "ball.json");
  const ParameterSet parameters(scene, {"/bodies/0/position/2", "/shapes/0/restitution", "/shapes/0/radius"});
  const std::string csv = folder.Write("ball.csv", "t,ball.z\n0.7,0.0\n");
  const Observations observations = ReadObservations(csv, scene.model);
  const LossGradient jet = JetLossGradient(scene.model, parameters, observations);
  const double z = 0.1 + e * v0 * tau - kG * tau * tau / 2;
  EXPECT_NEAR(jet.gradient[0], z * ((1 + e) * tau - e * t1) / t1, 1e-9);
  EXPECT_NEAR(jet.gradient[1], z * v0 * tau, 1e-9);
  testing::ExpectGradientsAgree(scene.model, parameters, observations);
}

// ---------------------------------------------------------------------------------------------------------------
// fit and study through contact

// A ball thrown from 1 m (restitution 0.6, friction 0.3 on the floor), 1 s: it bounces once before t = 1 s.
json Throw(double vx, double vz) {
  json ball = Particle("ball", {0.0, 0.0, 1.0}, {vx, 0.0, vz});
  ball["mass"] = 0.5;
  return {{"dimension", 3},
          {"bodies", {ball}},
          {"shapes",
           {{{"name", "ball_surface"},
             {"body", "ball"},
             {"type", "sphere"},
             {"radius", 0.1},
             {"restitution", 0.6},
             {"friction", 0.3}},
            {{"name", "floor"}, {"body", "world"}, {"type", "plane"}}}},
          {"effects", {{{"type", "gravity"}, {"acceleration", {0.0, 0.0, -kG}}}}},
          {"simulation", {{"integrator", "rk4"}, {"step", 1e-3}, {"duration", 1.0}}}};
}

TEST(ContactCommands, FitFindsTheThrowThatLandsTheBallInTheBasketAfterABounce) {
  // the basket: where the throw (2.5, 1.8) m/s puts the ball at t = 1 s, after its bounce at t = 0.65 s; fit starts
  // from (2, 1), whose ball is elsewhere then, and differentiates through the impact (its time moves with vz)
  const testing::TempFolder folder;
  VecX<double> q;
  const RunReport truth =
      Simulate<double>(Parse(Throw(2.5, 1.8)), RunOptions{}, [&](const Sample<double>& s) { q = s.q; });
  ASSERT_EQ(Impacts(truth).size(), 1u);
  const std::string basket =
      folder.Write("basket.csv", "t,ball.x,ball.z\n1.0," + json(q[0]).dump() + "," + json(q[2]).dump() + "\n");
  const std::string scene = folder.Write("throw.json", Throw(2.0, 1.0).dump());
  const testing::Outcome fitted = testing::RunTether(
      "fit " + scene + " --data " + basket + " --param /bodies/0/velocity/0 --param /bodies/0/velocity/2", folder);
  ASSERT_EQ(fitted.status, 0) << fitted.err;
  const json result = json::parse(fitted.out);
  EXPECT_NEAR(result["parameters"]["/bodies/0/velocity/0"].get<double>(), 2.5, 1e-8);
  EXPECT_NEAR(result["parameters"]["/bodies/0/velocity/2"].get<double>(), 1.8, 1e-8);
}

TEST(ContactCommands, AStudySweepsRestitutionAndFrictionAndMeasuresTheEnergyTheyTake) {
  // a ball dropped from z0 = 0.6 (restitution e, one impact within T = 0.5 s) and a block sliding at v0 = 3 m/s
  // (friction mu, still sliding at T): the energy lost is 1/2 m_b v_i^2 (1 - e^2) + 1/2 m_k (v0^2 - (v0 - mu g T)^2)
  // of E0 (gravity's zero at z = 0), the study's energy_drift; rms_position_error is against its own reference
  const testing::TempFolder folder;
  const double m_b = 0.5, m_k = 1.0, z0 = 0.6, v0 = 3.0, T = 0.5, inertia = 0.2 * 0.2 / 6;
  json ball = Particle("ball", {0.0, 1.0, z0});
  ball["mass"] = m_b;
  const json scene = {
      {"dimension", 3},
      {"bodies",
       {ball,
        {{"name", "block"},
         {"type", "rigid"},
         {"mass", m_k},
         {"inertia", {inertia, inertia, inertia}},
         {"position", {0.0, 0.0, 0.1}},
         {"velocity", {v0, 0.0, 0.0}}}}},
      {"shapes",
       {{{"name", "ball_surface"}, {"body", "ball"}, {"type", "sphere"}, {"radius", 0.1}, {"restitution", 0.6}},
        {{"name", "block_surface"}, {"body", "block"}, {"type", "box"}, {"size", {0.2, 0.2, 0.2}}, {"friction", 0.3}},
        {{"name", "floor"}, {"body", "world"}, {"type", "plane"}}}},
      {"effects", {{{"type", "gravity"}, {"acceleration", {0.0, 0.0, -kG}}}}},
      {"simulation", {{"integrator", "rk4"}, {"step", 1e-3}, {"duration", T}}}};
  folder.Write("both.json", scene.dump());
  const json study = {{"scene", "both.json"},
                      {"sweep", {{"/shapes/0/restitution", {0.3, 0.6, 0.9}}, {"/shapes/1/friction", {0.3, 0.6}}}},
                      {"metrics", {"rms_position_error", "energy_drift"}}};
  const testing::Outcome run =
      testing::RunTether("study " + folder.Write("study.json", study.dump()) + " --out " + folder.Path("out"), folder);
  ASSERT_EQ(run.status, 0) << run.err;
  std::ifstream results(folder.Path("out/results.csv"));
  std::string line;
  std::getline(results, line);
  EXPECT_EQ(line, "/shapes/0/restitution,/shapes/1/friction,rms_position_error,energy_drift,status");
  const double e0 = m_b * kG * z0 + 0.5 * m_k * v0 * v0 + m_k * kG * 0.1, v_impact_squared = 2.0 * kG * (z0 - 0.1);
  int rows = 0;
  while (std::getline(results, line)) {
    double e = 0, mu = 0, rms = 0, drift = 0;
    char status[8] = {};
    ASSERT_EQ(std::sscanf(line.c_str(), "%lf,%lf,%lf,%lf,%7s", &e, &mu, &rms, &drift, status), 5) << line;
    const double slid = v0 - mu * kG * T;
    const double lost = 0.5 * m_b * v_impact_squared * (1 - e * e) + 0.5 * m_k * (v0 * v0 - slid * slid);
    EXPECT_STREQ(status, "ok");
    EXPECT_NEAR(drift, lost / e0, 1e-9) << line;
    EXPECT_LT(rms, 1e-9) << line;
    ++rows;
  }
  EXPECT_EQ(rows, 6);
}

// The README's examples (docs/examples/contact/make_recordings.py): a ball's restitution (0.8 in the truth) and a
// cube's friction (0.35) identified from their recordings, each within three standard deviations.
TEST(ContactIdentification, TheReadmesRestitutionAndFrictionAreIdentifiedFromTheirRecordings) {
  const testing::TempFolder folder;
  const std::string example = std::string(TETHER_SOURCE_DIR) + "/docs/examples/contact/";
  struct Case {
    const char* guess;
    const char* data;
    const char* pointer;
    double truth;
  };
  for (const Case& c : {Case{"ball_guess.json", "bounces.csv", "/shapes/0/restitution", 0.8},
                        Case{"block_guess.json", "slide.csv", "/shapes/0/friction", 0.35}}) {
    const testing::Outcome identified = testing::RunTether(
        "identify " + example + c.guess + " --data " + example + c.data + " --param " + c.pointer, folder);
    ASSERT_EQ(identified.status, 0) << identified.err;
    const json result = json::parse(identified.out);
    const double estimate = result["parameters"][c.pointer], deviation = result["standard_deviation"][c.pointer];
    EXPECT_LT(std::abs(estimate - c.truth), 3 * deviation) << c.pointer << " " << estimate << " +- " << deviation;
    EXPECT_LT(deviation, 1e-4) << c.pointer;
  }
}

}  // namespace
}  // namespace tether
