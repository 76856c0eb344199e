// Joint limits (unilateral_events.h) against closed forms: a uniform rod on a pin swinging into a stop at the vertical
// (quarter swings sqrt(I / (m g d)) K(sin(theta / 2)), rebound amplitudes 1 - cos theta' = e^2 (1 - cos theta)),
// released from a limit the instant a motor's torque exceeds gravity's, energy kept with e = 1 over hundreds of
// impacts, rk4's fourth order across impacts, Jet gradients across an impact against central differences that
// keep the number of events, a Zeno sequence that ends captured, a grazing impact, 3D hinge and prismatic limits,
// and a range never reached that changes nothing; the active-set solve (active_set.h) on its own.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <string>
#include <vector>

#include "test_files.h"
#include "test_scenes.h"
#include "tether/autodiff/adjoint.h"
#include "tether/autodiff/residuals.h"
#include "tether/dynamics/constraints/active_set.h"
#include "tether/dynamics/integration/stepper.h"
#include "tether/dynamics/io/scene_reader.h"

namespace tether {
namespace {

using nlohmann::json;
using testing::EllipticK;
using testing::SceneFromJson;

constexpr double kG = 9.81;
constexpr double kInertiaAtPin = 1.0 / 3.0, kArm = 0.5;  // a uniform 1 kg, 1 m rod about its end

// the time from amplitude theta to the vertical
double QuarterSwing(double theta) { return std::sqrt(kInertiaAtPin / (kG * kArm)) * EllipticK(std::sin(theta / 2)); }

// the rod's rate at the vertical after falling from amplitude theta
double RateAtTheVertical(double theta) { return std::sqrt(2 * kG * kArm * (1 - std::cos(theta)) / kInertiaAtPin); }

// The rod hangs from the world's origin by a named pin "hinge" at its end, at `theta` from the downward vertical
// (counter-clockwise positive), turning at `omega`; `range` and `restitution` on the pin.
json Rod(double theta, double omega, const json& range, double restitution, double duration, double step = 1e-3) {
  const double a = -M_PI / 2 + theta;
  return {{"dimension", 2},
          {"bodies",
           {{{"name", "rod"},
             {"type", "rigid"},
             {"mass", 1.0},
             {"inertia", 1.0 / 12.0},
             {"position", {0.5 * std::cos(a), 0.5 * std::sin(a)}},
             {"angle", a},
             {"velocity", {-0.5 * omega * std::sin(a), 0.5 * omega * std::cos(a)}},
             {"angular_velocity", omega}}}},
          {"constraints",
           {{{"type", "pin"},
             {"name", "hinge"},
             {"bodies", {"world", "rod"}},
             {"points", {{0.0, 0.0}, {-0.5, 0.0}}},
             {"angle", theta},
             {"range", range},
             {"restitution", restitution}}}},
          {"effects", {{{"type", "gravity"}, {"acceleration", {0.0, -kG}}}}},
          {"simulation", {{"integrator", "rk4"}, {"step", step}, {"duration", duration}}}};
}

Model<double> Parse(const json& document) { return ParseScene(document, "limits.json").model; }

std::vector<RunEvent> Events(const std::vector<RunEvent>& events, const std::string& kind) {
  std::vector<RunEvent> out;
  for (const RunEvent& e : events) {
    if (e.kind == kind) out.push_back(e);
  }
  return out;
}

// The hinge angle at the end of a run, with its report.
double FinalAngle(const Model<double>& model, RunReport* report = nullptr) {
  double angle = NAN;
  const RunReport r = Simulate<double>(model, RunOptions{}, [&](const Sample<double>& s) { angle = s.coordinates[0]; });
  if (report) *report = r;
  return angle;
}

// the active-set solve on three coupled rows, S mu = b on the rows in the set (S = [[2, 1, 0], [1, 2, 1],
// [0, 1, 2]], b = (1, -1, -0.2)): with all three mu = (1.2, -1.4, 0.6), the second pulls; without it
// mu = (0.5, -0.1), the third pulls; the first alone pushes (0.5)
TEST(ActiveSet, LeavesOutThePullingRowsOneAtATimeAndKeepsWhatItIsTold) {
  const Eigen::Matrix3d S = (Eigen::Matrix3d() << 2, 1, 0, 1, 2, 1, 0, 1, 2).finished();
  const Eigen::Vector3d b(1.0, -1.0, -0.2);
  int solves = 0;
  auto pushes = [&](const std::vector<char>& set, std::vector<int>* rows, std::vector<double>* push) {
    ++solves;
    rows->clear();
    for (int i = 0; i < 3; ++i) {
      if (set[i]) rows->push_back(i);
    }
    const int n = static_cast<int>(rows->size());
    Eigen::MatrixXd s(n, n);
    Eigen::VectorXd r(n);
    for (int i = 0; i < n; ++i) {
      r[i] = b[(*rows)[i]];
      for (int j = 0; j < n; ++j) s(i, j) = S((*rows)[i], (*rows)[j]);
    }
    const Eigen::VectorXd mu = s.ldlt().solve(r);
    push->assign(mu.data(), mu.data() + n);
    return true;
  };
  std::vector<char> set = {1, 1, 1};
  ASSERT_TRUE(SolveActiveSet(&set, {0, 0, 0}, false, pushes));
  EXPECT_EQ(set, (std::vector<char>{1, 0, 0}));
  EXPECT_EQ(solves, 3);
  set = {1, 1, 1};
  solves = 0;
  ASSERT_TRUE(SolveActiveSet(&set, {0, 1, 0}, false, pushes));  // the second kept though it pulls
  EXPECT_EQ(set, (std::vector<char>{1, 1, 1}));
  EXPECT_EQ(solves, 1);
  set = {1, 0, 0};  // a push of exactly zero stays unless released
  auto zero = [](const std::vector<char>& s, std::vector<int>* rows, std::vector<double>* push) {
    *rows = s[0] ? std::vector<int>{0} : std::vector<int>{};
    *push = std::vector<double>(rows->size(), 0.0);
    return true;
  };
  ASSERT_TRUE(SolveActiveSet(&set, {0, 0, 0}, false, zero));
  EXPECT_EQ(set[0], 1);
  ASSERT_TRUE(SolveActiveSet(&set, {0, 0, 0}, true, zero));
  EXPECT_EQ(set[0], 0);
}

TEST(JointLimits, ARodSwingsIntoAStopAtTheClosedFormTimesAndRates) {
  const double theta0 = M_PI / 3, e = 0.5;
  RunReport report;
  FinalAngle(Parse(Rod(theta0, 0.0, {0.0, nullptr}, e, 2.5)), &report);
  const std::vector<RunEvent> impacts = Events(report.events, "impact");
  ASSERT_GE(impacts.size(), 3u);
  double amplitude = theta0, t = 0.0;
  for (int k = 0; k < 3; ++k) {
    t += (k == 0 ? 1 : 2) * QuarterSwing(amplitude);
    const double rate = RateAtTheVertical(amplitude);
    EXPECT_NEAR(impacts[k].t, t, 1e-9) << "impact " << k;
    EXPECT_EQ(impacts[k].constraint, "hinge");
    EXPECT_NEAR(impacts[k].speed_before, -rate, 1e-9 * rate) << "impact " << k;
    EXPECT_NEAR(impacts[k].speed_after, e * rate, 1e-9 * rate) << "impact " << k;
    amplitude = std::acos(1 - e * e * (1 - std::cos(amplitude)));  // the rebound's amplitude
  }
}

TEST(JointLimits, TheRodNeverPassesItsStop) {
  double lowest = 0.0;
  Simulate<double>(Parse(Rod(M_PI / 3, 0.0, {0.0, nullptr}, 0.3, 3.0)), RunOptions{},
                   [&](const Sample<double>& s) { lowest = std::min(lowest, s.coordinates[0]); });
  EXPECT_GT(lowest, -1e-12);
}

TEST(JointLimits, AnElasticStopKeepsTheEnergyOverHundredsOfImpacts) {
  // between stops 0.1 rad apart at about 5 rad/s: an impact every 20 ms; at 0.5 ms rk4's own drift over the run
  // is 3e-10 of the kinetic energy (16 times that at 1 ms: the impacts add nothing measurable)
  const Model<double> model = Parse(Rod(0.05, 5.0, {0.0, 0.1}, 1.0, 8.0, 5e-4));
  std::vector<double> energy;
  const RunReport report =
      Simulate<double>(model, RunOptions{}, [&](const Sample<double>& s) { energy.push_back(s.energy); });
  EXPECT_GT(Events(report.events, "impact").size(), 300u);
  double drift = 0.0;
  for (double x : energy) drift = std::max(drift, std::abs(x - energy.front()));
  EXPECT_LT(drift / (0.5 * kInertiaAtPin * 5.0 * 5.0), 1e-9);  // of the kinetic energy
}

TEST(JointLimits, ReleasesTheInstantAMotorsTorqueExceedsGravitys) {
  json scene = Rod(0.0, 0.0, {0.0, 2.0}, 0.0, 0.9);
  scene["bodies"][0]["position"] = {0.5, 0.0};  // horizontal, resting on its low bound
  scene["bodies"][0]["angle"] = 0.0;
  scene["constraints"][0]["angle"] = 0.0;
  scene["constraints"][0].erase("restitution");
  scene["effects"].push_back(
      {{"type", "joint_torque"}, {"joint", "hinge"}, {"schedule", {{"times", {0.0, 1.0}}, {"values", {0.0, 10.0}}}}});
  double crept = 0.0;
  const RunReport report = Simulate<double>(Parse(scene), RunOptions{}, [&](const Sample<double>& s) {
    if (s.t < 0.49) crept = std::max(crept, std::abs(s.coordinates[0]));
  });
  const std::vector<RunEvent> releases = Events(report.events, "release");
  ASSERT_EQ(releases.size(), 1u);
  EXPECT_NEAR(releases[0].t, kG * kArm / 10.0, 1e-10);  // 10 t = m g d
  EXPECT_LT(crept, 1e-12);
  EXPECT_TRUE(Events(report.events, "impact").empty());
}

TEST(JointLimits, Rk4KeepsItsFourthOrderAcrossImpacts) {
  // two impacts before 1.5 s with a damping torque (the motion has no closed form; a run at 1/16 ms is the
  // reference)
  auto run = [](double step) {
    json scene = Rod(M_PI / 3, 0.0, {0.0, nullptr}, 0.7, 1.5, step);
    scene["effects"].push_back({{"type", "damping"}, {"coefficient", 0.0}, {"angular_coefficient", 0.05}});
    RunReport report;
    const double angle = FinalAngle(Parse(scene), &report);
    EXPECT_EQ(Events(report.events, "impact").size(), 2u);
    return angle;
  };
  const double reference = run(1e-3 / 16);
  const double e1 = std::abs(run(0.02) - reference), e2 = std::abs(run(0.01) - reference);
  const double e3 = std::abs(run(0.005) - reference);
  EXPECT_GT(std::log2(e1 / e2), 3.5) << e1 << " " << e2;
  EXPECT_GT(std::log2(e2 / e3), 3.5) << e2 << " " << e3;
}

TEST(JointLimits, AZenoSequenceEndsHeldOnTheStop) {
  // a stop at 0.5 rad, which gravity presses the rod onto (a bouncing ball: the flights shrink with the rebound
  // speed, e = 0.5, and add up to a finite time); dropped from 0.8 rad
  RunReport report;
  const double angle = FinalAngle(Parse(Rod(0.8, 0.0, {0.5, nullptr}, 0.5, 2.0)), &report);
  const std::vector<RunEvent> impacts = Events(report.events, "impact");
  ASSERT_GT(impacts.size(), 10u);
  EXPECT_LT(impacts.size(), 100u);
  EXPECT_NEAR(impacts.back().speed_after, 0.0, 1e-15);  // the last one captured
  EXPECT_LT(impacts.back().t, 1.0);
  EXPECT_NEAR(angle, 0.5, 1e-12);
  EXPECT_TRUE(Events(report.events, "release").empty());
}

TEST(JointLimits, ATouchAtTheStartIsHeldWithoutAnImpulse) {
  // at 1e-20 rad above the stop, at rest: the rod arrives slower than kRestingSpeed, a touch
  RunReport report;
  const double angle = FinalAngle(Parse(Rod(1e-20, 0.0, {0.0, nullptr}, 1.0, 0.5)), &report);
  EXPECT_TRUE(Events(report.events, "impact").empty());
  EXPECT_NEAR(angle, 0.0, 1e-15);
}

TEST(JointLimits, AGrazingImpactLeavesOutItsTimeSensitivityWithAWarning) {
  // without gravity, from 1e-8 rad at -5e-7 rad/s (below kGrazingSpeed): with Jets, a warning and finite numbers
  json scene = Rod(1e-8, -5e-7, {0.0, nullptr}, 1.0, 0.1);
  scene["effects"] = json::array();
  Model<Jet> model = CastModel<Jet>(Parse(scene));
  model.joints[0].range.restitution.v[0] = 1.0;
  bool finite = true;
  const RunReport report = Simulate<Jet>(model, RunOptions{}, [&](const Sample<Jet>& s) {
    for (int i = 0; i < s.q.size(); ++i) finite = finite && std::isfinite(s.q[i].a) && s.q[i].v.allFinite();
  });
  EXPECT_TRUE(finite);
  ASSERT_FALSE(Events(report.events, "impact").empty());
  bool warned = false;
  for (const std::string& w : report.warnings)
    warned = warned || w.find("grazing impact on hinge") != std::string::npos;
  EXPECT_TRUE(warned);
}

TEST(JointLimits, ARangeNeverReachedChangesNothing) {
  json limited = Rod(M_PI / 3, 0.0, {-2.0, 2.0}, 0.5, 1.0);
  json free = limited;
  free["constraints"][0].erase("range");
  free["constraints"][0].erase("restitution");
  std::vector<double> a, b;
  Simulate<double>(Parse(limited), RunOptions{}, [&](const Sample<double>& s) { a.push_back(s.q[2]); });
  Simulate<double>(Parse(free), RunOptions{}, [&](const Sample<double>& s) { b.push_back(s.q[2]); });
  EXPECT_EQ(a, b);
}

// A 3D hinge about z between the world and a rod hanging along -y: the 2D rod's motion, impacts included.
TEST(JointLimits, A3dHingeStopsAsThePlanarPin) {
  const double theta0 = M_PI / 3;
  const json scene = {{"dimension", 3},
                      {"bodies",
                       {{{"name", "rod"},
                         {"type", "rigid"},
                         {"mass", 1.0},
                         {"inertia", {1.0 / 12.0, 1e-4, 1.0 / 12.0}},
                         {"position", {0.5 * std::sin(theta0), -0.5 * std::cos(theta0), 0.0}},
                         {"orientation", {std::cos(theta0 / 2), 0.0, 0.0, std::sin(theta0 / 2)}}}}},
                      {"constraints",
                       {{{"type", "hinge"},
                         {"name", "hinge"},
                         {"bodies", {"world", "rod"}},
                         {"points", {{0.0, 0.0, 0.0}, {0.0, 0.5, 0.0}}},
                         {"axis", {0.0, 0.0, 1.0}},
                         {"angle", theta0},
                         {"range", {0.0, nullptr}},
                         {"restitution", 0.5}}}},
                      {"effects", {{{"type", "gravity"}, {"acceleration", {0.0, -kG, 0.0}}}}},
                      {"simulation", {{"integrator", "rk4"}, {"step", 1e-3}, {"duration", 1.0}}}};
  RunReport report;
  FinalAngle(Parse(scene), &report);
  const std::vector<RunEvent> impacts = Events(report.events, "impact");
  ASSERT_GE(impacts.size(), 1u);
  EXPECT_NEAR(impacts[0].t, QuarterSwing(theta0), 1e-9);
  EXPECT_NEAR(impacts[0].speed_after, -0.5 * impacts[0].speed_before, 1e-9);
  EXPECT_NEAR(impacts[0].speed_before, -RateAtTheVertical(theta0), 1e-8);
}

// A block sliding down a vertical prismatic rail onto a stop 0.2 m below: free fall, then a rebound at e = 0.8.
TEST(JointLimits, APrismaticStopCatchesAFallingBlock) {
  const json scene = {{"dimension", 3},
                      {"bodies",
                       {{{"name", "block"},
                         {"type", "rigid"},
                         {"mass", 2.0},
                         {"inertia", {0.1, 0.1, 0.1}},
                         {"position", {0.3, 0.0, 0.0}},
                         {"velocity", {0.0, 0.0, 0.0}}}}},
                      {"constraints",
                       {{{"type", "prismatic"},
                         {"name", "rail"},
                         {"bodies", {"world", "block"}},
                         {"points", {{0.3, 0.0, 0.0}, {0.0, 0.0, 0.0}}},
                         {"axis", {0.0, 0.0, 1.0}},
                         {"range", {-0.2, 0.5}},
                         {"restitution", 0.8}}}},
                      {"effects", {{{"type", "gravity"}, {"acceleration", {0.0, 0.0, -kG}}}}},
                      {"simulation", {{"integrator", "rk4"}, {"step", 1e-3}, {"duration", 0.5}}}};
  RunReport report;
  const Model<double> model = Parse(scene);
  double z = NAN;
  report = Simulate<double>(model, RunOptions{}, [&](const Sample<double>& s) { z = s.q[2]; });
  const std::vector<RunEvent> impacts = Events(report.events, "impact");
  ASSERT_EQ(impacts.size(), 1u);
  const double t1 = std::sqrt(2 * 0.2 / kG), v1 = kG * t1;
  EXPECT_NEAR(impacts[0].t, t1, 1e-10);
  EXPECT_NEAR(impacts[0].speed_before, -v1, 1e-9);
  EXPECT_NEAR(impacts[0].speed_after, 0.8 * v1, 1e-9);
  const double tau = 0.5 - t1;  // rk4 is exact on the parabolas
  EXPECT_NEAR(z, -0.2 + 0.8 * v1 * tau - kG * tau * tau / 2, 1e-10);
}

// ---------------------------------------------------------------------------------------------------------------
// gradients through impacts

struct BounceProblem {
  Scene scene;
  ParameterSet parameters;
  Observations observations;
};

// The rod launched at 2 rad/s towards its stop at -0.1 rad, observed at times after the impact.
BounceProblem Bounce(const testing::TempFolder& folder) {
  BounceProblem p;
  p.scene = ParseScene(Rod(0.2, -2.0, {-0.1, nullptr}, 0.6, 0.6), "bounce.json");
  p.parameters =
      ParameterSet(p.scene, {"/bodies/0/angular_velocity", "/constraints/0/restitution", "/constraints/0/range/0"});
  const std::string csv = folder.Write("bounce.csv", "t,hinge.angle,hinge.omega\n0.3,0.1,0.5\n0.55,0.2,-1\n");
  p.observations = ReadObservations(csv, p.scene.model);
  return p;
}

TEST(JointLimitGradients, JetsAcrossAnImpactMatchCentralDifferences) {
  testing::TempFolder folder;
  const BounceProblem p = Bounce(folder);
  RunReport report;
  FinalAngle(p.scene.model, &report);
  ASSERT_EQ(Events(report.events, "impact").size(), 1u);  // the differences keep the one impact
  const LossGradient jet = JetLossGradient(p.scene.model, p.parameters, p.observations);
  const LossGradient central = CentralDifferenceLossGradient(p.scene.model, p.parameters, p.observations);
  for (size_t i = 0; i < jet.gradient.size(); ++i) {
    EXPECT_NE(jet.gradient[i], 0.0) << i;
    EXPECT_NEAR(jet.gradient[i], central.gradient[i], 1e-6 * std::abs(central.gradient[i])) << i;
  }
}

TEST(JointLimitGradients, TheAdjointAcrossAnImpactEqualsJets) {
  testing::TempFolder folder;
  const BounceProblem p = Bounce(folder);
  const LossGradient jet = JetLossGradient(p.scene.model, p.parameters, p.observations);
  for (std::int64_t interval : {1, 7}) {  // every state kept, or checkpoints every 7 steps
    const LossGradient adjoint = AdjointLossGradient(p.scene.model, p.parameters, p.observations, interval);
    for (size_t i = 0; i < jet.gradient.size(); ++i) {
      EXPECT_NEAR(adjoint.gradient[i], jet.gradient[i], 1e-9 * std::abs(jet.gradient[i])) << i << " K " << interval;
    }
  }
}

// The README's example (docs/examples/limits/make_recording.py): the stop's restitution, 0.75 in the truth,
// identified from the hinge's encoder through four impacts.
TEST(JointLimitGradients, TheReadmesRestitutionIsIdentifiedFromItsRecording) {
  const testing::TempFolder folder;
  const std::string example = std::string(TETHER_SOURCE_DIR) + "/docs/examples/limits/";
  const testing::Outcome identified = testing::RunTether(
      "identify " + example + "guess.json --data " + example + "bounces.csv --param /constraints/0/restitution",
      folder);
  ASSERT_EQ(identified.status, 0) << identified.err;
  const json result = json::parse(identified.out);
  const double e = result["parameters"]["/constraints/0/restitution"];
  const double deviation = result["standard_deviation"]["/constraints/0/restitution"];
  EXPECT_LT(std::abs(e - 0.75), 3 * deviation) << e << " +- " << deviation;
  EXPECT_LT(deviation, 1e-4);
}

// fit through an impact: a rod spinning about its centre (no gravity) at omega0 < 0 strikes a stop at -0.4 rad
// at t1 = 0.4 / |omega0| and leaves at e |omega0|, so at 1 s its angle is -0.4 + e (|omega0| - 0.4): the target
// 0.08 at e = 0.8 is met by omega0 = -1 alone, which the fit reaches from -0.8 (whose impact comes 0.1 s later)
TEST(JointLimitGradients, FitFindsTheSpinThatBouncesOffTheStopOntoATarget) {
  const testing::TempFolder folder;
  const json spinner = {{"dimension", 2},
                        {"bodies",
                         {{{"name", "rod"},
                           {"type", "rigid"},
                           {"mass", 1.0},
                           {"inertia", 1.0 / 12.0},
                           {"position", {0.0, 0.0}},
                           {"velocity", {0.0, 0.0}},
                           {"angular_velocity", -0.8}}}},
                        {"constraints",
                         {{{"type", "pin"},
                           {"name", "hinge"},
                           {"bodies", {"world", "rod"}},
                           {"points", {{0.0, 0.0}, {0.0, 0.0}}},
                           {"range", {-0.4, nullptr}},
                           {"restitution", 0.8}}}},
                        {"simulation", {{"integrator", "rk4"}, {"step", 1e-3}, {"duration", 1.0}}}};
  const std::string scene = folder.Write("spinner.json", spinner.dump());
  const std::string targets = folder.Write("targets.csv", "t,hinge.angle\n1.0,0.08\n");
  const testing::Outcome fitted =
      testing::RunTether("fit " + scene + " --data " + targets + " --param /bodies/0/angular_velocity", folder);
  ASSERT_EQ(fitted.status, 0) << fitted.err;
  EXPECT_NEAR(json::parse(fitted.out)["parameters"]["/bodies/0/angular_velocity"].get<double>(), -1.0, 1e-9);
}

// ---------------------------------------------------------------------------------------------------------------
// the scene file

TEST(JointLimitScenes, BadRangesAreRefusedNamingThePointer) {
  auto refused = [](json scene, const std::string& pointer) {
    try {
      ParseScene(scene, "limits.json");
    } catch (const InputError& e) {
      return std::string(e.what()).find("limits.json: " + pointer) != std::string::npos;
    }
    return false;
  };
  json scene = Rod(0.5, 0.0, {1.0, 0.0}, 0.5, 1.0);
  EXPECT_TRUE(refused(scene, "/constraints/0/range"));  // low above high
  scene = Rod(0.5, 0.0, {0.6, nullptr}, 0.5, 1.0);
  EXPECT_TRUE(refused(scene, "/constraints/0/range"));  // starts outside
  scene = Rod(0.5, 0.0, {nullptr, 0.4}, 0.5, 1.0);
  EXPECT_TRUE(refused(scene, "/constraints/0/range"));
  scene = Rod(0.5, 0.0, {0.0, nullptr}, -1.0, 1.0);
  EXPECT_TRUE(refused(scene, "/constraints/0/restitution"));
  scene = Rod(0.5, 0.0, {0.0, nullptr}, 1.5, 1.0);
  EXPECT_TRUE(refused(scene, "/constraints/0/restitution"));
  scene = Rod(0.5, 0.0, {0.0, "a"}, 0.5, 1.0);
  EXPECT_TRUE(refused(scene, "/constraints/0/range/1"));
  scene = Rod(0.5, 0.0, {0.0, 1.0, 2.0}, 0.5, 1.0);
  EXPECT_TRUE(refused(scene, "/constraints/0/range"));
  scene = Rod(0.5, 0.0, {0.0, nullptr}, 0.5, 1.0);
  scene["constraints"][0].erase("range");
  EXPECT_TRUE(refused(scene, "/constraints/0/restitution"));  // a restitution with no range
  scene = {{"bodies", {{{"name", "p"}, {"type", "particle"}, {"mass", 1.0}, {"position", {1.0, 0.0}}}}},
           {"constraints",
            {{{"type", "pin"},
              {"name", "pin"},
              {"bodies", {"world", "p"}},
              {"points", {{1.0, 0.0}, {0.0, 0.0}}},
              {"range", {0.0, 1.0}}}}}};
  EXPECT_TRUE(refused(scene, "/constraints/0/range"));  // a particle's pin has no angle
}

TEST(JointLimitScenes, AnUnnamedLimitedJointIsLimitedAndNamedByItsPointer) {
  json scene = Rod(M_PI / 3, 0.0, {0.0, nullptr}, 0.5, 0.5);
  scene["constraints"][0].erase("name");
  const RunReport report = Simulate<double>(Parse(scene), RunOptions{}, [](const Sample<double>&) {});
  ASSERT_FALSE(Events(report.events, "impact").empty());
  const RunEvent& impact = report.events[0];
  EXPECT_EQ(impact.constraint, "/constraints/0");
  // where: the joint, at the pivot; the impulse: the angular momentum about it, I (g'+ - g'-) with I = m L^2 / 3
  EXPECT_LT(impact.point.norm(), 1e-9);
  EXPECT_EQ(impact.normal.norm(), 0.0);
  EXPECT_NEAR(impact.impulse, (impact.speed_after - impact.speed_before) / 3.0, 1e-9);
}

TEST(JointLimitScenes, AnEmptyShapesListIsTheSceneWithoutThem) {
  json scene = Rod(M_PI / 3, 0.0, {0.0, nullptr}, 0.5, 0.5);
  scene["shapes"] = json::array();
  const Model<double> model = Parse(scene);
  EXPECT_TRUE(model.shapes.empty());
  EXPECT_TRUE(BuildContactGeometry(model).features.empty());
}

}  // namespace
}  // namespace tether
