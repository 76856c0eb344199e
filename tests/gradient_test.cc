// Loss gradients against observations (residuals.h): the Jet gradient (JetLossGradient through ParameterSet and
// ObservationResiduals) against an accurate central-difference reference, for every differentiable pointer kind
// of parameters.h, on particle, rigid-body (pins), slider, spring and damping scenes, under every integrator and
// every stabilization. The observations are made here: a 'truth' scene with every parameter perturbed is
// simulated and a few of its columns (a coordinate, a velocity and the energy, with one cell left empty) are
// written to a CSV at times on and off the step grid.
//
// The discrete adjoint (adjoint.h) equals the Jet gradient on every combination, and checkpointing does not
// change its numbers.
//
// Also: the implicit-function KKT path equals the Jet-factorization oracle on a dense and a sparse constraint
// system; more than kJetStride parameters at once give the gradients of one-at-a-time runs; the loss is half the
// sum of squared differences computed independently from a plain run; and stop times are sampled exactly.
#include <gtest/gtest.h>
#include <stdlib.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "test_files.h"
#include "test_scenes.h"
#include "tether/autodiff/adjoint.h"
#include "tether/autodiff/residuals.h"
#include "tether/dynamics/io/scene_reader.h"
#include "tether/dynamics/io/trajectory_csv.h"
#include "tether/dynamics/model/kinematics.h"
#include "tether/dynamics/solvers/schur_solver.h"

namespace tether {
namespace {

using ::tether::testing::CsvCells;

using nlohmann::json;

constexpr double kDuration = 0.3;  // s: short windows keep every mechanism far from singular configurations
constexpr double kStep = 2e-3;     // s
constexpr double kRk45Tolerance = 1e-10;  // tight, so that step-size control barely depends on the parameters
// Observation times: on the grid (0.05, 0.2, the end) and off it (0.1234, 0.2777).
const std::vector<double> kTimes = {0.05, 0.1234, 0.2, 0.2777, kDuration};
// Nominal Baumgarte gains (omega = 10 rad/s, critically damped).
constexpr double kAlpha = 20.0, kBeta = 100.0;

// Jet gradient vs the central-difference reference: |g_jet - g_ref| <= kAgreement * max(1e-3 scale, |g_ref|),
// where scale is the largest |g_ref| of the scene's parameters.
constexpr double kAgreement = 1e-6;
// Central-difference step: kRelativeStep * max(|p|, kSmallestSize), then halved twice for Richardson
// extrapolation (error O(h^6)); 1e-3 keeps round-off (~1e-14 |L| / h) and the parameter-dependence of
// discrete choices (projection iteration counts, rk45 step sizes, both ~1e-12) far below kAgreement.
constexpr double kRelativeStep = 1e-3;
constexpr double kSmallestSize = 0.1;

// ---------------------------------------------------------------------------------------------------------------
// scenes

json Point(const Vec3<double>& p, int dimension = 2) {
  json out = json::array();
  for (int k = 0; k < dimension; ++k) out.push_back(p[k]);
  return out;
}

Vec3<double> V(double x, double y, double z = 0.0) { return Vec3<double>(x, y, z); }

// World velocity of a body point at r (relative to the centre) of a planar body turning at omega.
Vec3<double> PointVelocity(const Vec3<double>& v, double omega, const Vec3<double>& r) { return v + omega * Perp(r); }

struct GradientScene {
  std::string name;
  json document;                         // without "simulation" and "stabilization"
  std::vector<std::string> parameters;   // /stabilization/alpha and beta are added under baumgarte
  std::vector<std::string> columns;      // observed columns
};

// A double pendulum of two particles on distance constraints with offset attachment points, under gravity,
// damping, a constant force and a scheduled force.
GradientScene Particles() {
  const Vec3<double> pivot = V(0.05, 0.02), a = V(0.5, -0.4), b = V(0.8, -0.9);
  const Vec3<double> a_point = V(0.02, -0.01), b_point = V(0.0, 0.03);
  json d = {
      {"dimension", 2},
      {"bodies",
       {{{"name", "a"}, {"type", "particle"}, {"mass", 1.0}, {"position", Point(a)}, {"velocity", {0.3, 0.2}}},
        {{"name", "b"}, {"type", "particle"}, {"mass", 0.7}, {"position", Point(b)}, {"velocity", {-0.4, 0.5}}}}},
      {"constraints",
       {{{"type", "distance"}, {"bodies", {"world", "a"}}, {"points", {Point(pivot), {0.0, 0.0}}},
         {"length", (a - pivot).norm()}},
        {{"type", "distance"}, {"bodies", {"a", "b"}}, {"points", {Point(a_point), Point(b_point)}},
         {"length", ((b + b_point) - (a + a_point)).norm()}}}},
      {"effects",
       {{{"type", "gravity"}, {"acceleration", {0.3, -9.81}}},
        {{"type", "damping"}, {"coefficient", 0.4}},
        {{"type", "force"}, {"body", "b"}, {"value", {0.5, 1.0}}},
        {{"type", "force"}, {"body", "a"},
         {"schedule", {{"times", {0.0, 0.1, 0.25}}, {"values", {{0.0, 0.0}, {1.0, -0.5}, {0.3, 0.8}}}}}}}}};
  return {"Particles", d,
          {"/bodies/0/mass", "/bodies/1/mass", "/bodies/1/position/0", "/bodies/0/position/1", "/bodies/0/velocity/1",
           "/bodies/1/velocity/0", "/constraints/0/length", "/constraints/1/length", "/constraints/0/points/0/1",
           "/constraints/1/points/0/0", "/constraints/1/points/1/1", "/effects/0/acceleration/0",
           "/effects/0/acceleration/1", "/effects/1/coefficient", "/effects/2/value/1",
           "/effects/3/schedule/values/1/0", "/effects/3/schedule/values/2/1"},
          {"a.x", "b.y", "b.vx", "energy"}};
}

// Two rigid bars on pins (an open chain from a world pivot), with a torque, a scheduled torque, a force at a
// point of the lower bar and linear plus angular damping. The initial velocities are consistent.
GradientScene RigidPins() {
  const double l1 = 0.6, l2 = 0.5, angle1 = -1.0, angle2 = -0.4, omega1 = 2.0, omega2 = -1.0;
  const Vec3<double> pivot = V(0.0, 0.1);
  const Vec3<double> c1 = pivot + RotatePlanar(angle1, V(l1 / 2, 0.0));
  const Vec3<double> joint = pivot + RotatePlanar(angle1, V(l1, 0.0));
  const Vec3<double> c2 = joint + RotatePlanar(angle2, V(l2 / 2, 0.0));
  const Vec3<double> v1 = PointVelocity(Vec3<double>::Zero(), omega1, c1 - pivot);
  const Vec3<double> v2 = PointVelocity(PointVelocity(v1, omega1, joint - c1), omega2, c2 - joint);
  json d = {
      {"dimension", 2},
      {"bodies",
       {{{"name", "upper"}, {"type", "rigid"}, {"mass", 1.2}, {"inertia", 1.2 * l1 * l1 / 12}, {"position", Point(c1)},
         {"angle", angle1}, {"velocity", Point(v1)}, {"angular_velocity", omega1}},
        {{"name", "lower"}, {"type", "rigid"}, {"mass", 0.8}, {"inertia", 0.8 * l2 * l2 / 12}, {"position", Point(c2)},
         {"angle", angle2}, {"velocity", Point(v2)}, {"angular_velocity", omega2}}}},
      {"constraints",
       {{{"type", "pin"}, {"bodies", {"world", "upper"}}, {"points", {Point(pivot), {-l1 / 2, 0.0}}}},
        {{"type", "pin"}, {"bodies", {"upper", "lower"}}, {"points", {{l1 / 2, 0.0}, {-l2 / 2, 0.0}}}}}},
      {"effects",
       {{{"type", "gravity"}, {"acceleration", {0.0, -9.81}}},
        {{"type", "damping"}, {"coefficient", 0.2}, {"angular_coefficient", 0.05}},
        {{"type", "torque"}, {"body", "upper"}, {"value", 0.5}},
        {{"type", "torque"}, {"body", "lower"}, {"schedule", {{"times", {0.05, 0.2}}, {"values", {0.2, -0.3}}}}},
        {{"type", "force"}, {"body", "lower"}, {"point", {0.2, 0.05}}, {"value", {1.0, 0.5}}}}}};
  return {"RigidPins", d,
          {"/bodies/0/mass", "/bodies/1/inertia", "/bodies/0/angle", "/bodies/1/angle", "/bodies/1/angular_velocity",
           "/bodies/1/position/1", "/bodies/0/velocity/0", "/constraints/0/points/0/0", "/constraints/1/points/1/0",
           "/constraints/1/points/0/1", "/effects/1/angular_coefficient", "/effects/2/value",
           "/effects/3/schedule/values/0", "/effects/3/schedule/values/1", "/effects/4/point/0", "/effects/4/point/1",
           "/effects/4/value/0"},
          {"upper.angle", "lower.x", "lower.omega", "energy"}};
}

// A cart-pole on an inclined slider: a particle cart whose offset point slides along a line through a world
// point, pulled by a damped spring, with a rigid pole pinned to it.
GradientScene Slider() {
  const Vec3<double> rail = V(0.1, -0.05), axis = V(1.0, 0.5), cart_point = V(0.02, 0.01);
  const Vec3<double> unit = axis.normalized();
  const Vec3<double> cart = rail + 0.4 * unit - cart_point, cart_velocity = 0.3 * unit;
  const double pole = 0.5, angle = -1.2, omega = 1.0;
  const Vec3<double> centre = cart + RotatePlanar(angle, V(pole / 2, 0.0));
  const Vec3<double> pole_velocity = PointVelocity(cart_velocity, omega, centre - cart);
  json d = {
      {"dimension", 2},
      {"bodies",
       {{{"name", "cart"}, {"type", "particle"}, {"mass", 0.8}, {"position", Point(cart)},
         {"velocity", Point(cart_velocity)}},
        {{"name", "pole"}, {"type", "rigid"}, {"mass", 0.4}, {"inertia", 0.4 * pole * pole / 12},
         {"position", Point(centre)}, {"angle", angle}, {"velocity", Point(pole_velocity)},
         {"angular_velocity", omega}}}},
      {"constraints",
       {{{"type", "slider"}, {"bodies", {"world", "cart"}}, {"points", {Point(rail), Point(cart_point)}},
         {"axis", Point(axis)}},
        {{"type", "pin"}, {"bodies", {"cart", "pole"}}, {"points", {{0.0, 0.0}, {-pole / 2, 0.0}}}}}},
      {"effects",
       {{{"type", "gravity"}, {"acceleration", {0.0, -9.81}}},
        {{"type", "spring"}, {"bodies", {"world", "cart"}}, {"points", {Point(rail - unit), {0.0, 0.0}}},
         {"stiffness", 40.0}, {"rest_length", 1.5}, {"damping", 0.5}}}}};
  return {"Slider", d,
          {"/bodies/0/mass", "/bodies/1/inertia", "/constraints/0/points/0/0", "/constraints/0/points/0/1",
           "/constraints/0/points/1/0", "/constraints/0/points/1/1", "/constraints/0/axis/0", "/constraints/0/axis/1",
           "/constraints/1/points/1/0", "/effects/1/stiffness", "/effects/1/rest_length", "/effects/1/damping"},
          {"cart.x", "pole.angle", "cart.vy", "energy"}};
}

// A 3D dumbbell (two particles on a distance constraint) hanging from two damped springs with offset points.
GradientScene Springs() {
  const Vec3<double> p = V(0.3, 0.1, -0.5), q = V(0.5, -0.2, -0.9);
  json d = {
      {"dimension", 3},
      {"bodies",
       {{{"name", "p"}, {"type", "particle"}, {"mass", 1.0}, {"position", Point(p, 3)}, {"velocity", {0.1, 0.2, 0.0}}},
        {{"name", "q"}, {"type", "particle"}, {"mass", 0.6}, {"position", Point(q, 3)}, {"velocity", {0.0, 0.1, 0.3}}}}},
      {"constraints", {{{"type", "distance"}, {"bodies", {"p", "q"}}, {"length", (q - p).norm()}}}},
      {"effects",
       {{{"type", "spring"}, {"bodies", {"world", "p"}}, {"points", {{0.0, 0.0, 0.1}, {0.02, 0.0, 0.0}}},
         {"stiffness", 30.0}, {"rest_length", 0.4}, {"damping", 0.5}},
        {{"type", "spring"}, {"bodies", {"world", "q"}}, {"points", {{0.4, 0.0, 0.0}, {0.0, 0.01, 0.02}}},
         {"stiffness", 50.0}, {"rest_length", 0.7}, {"damping", 0.2}},
        {{"type", "gravity"}, {"acceleration", {0.0, 0.0, -9.81}}}}}};
  return {"Springs", d,
          {"/bodies/1/mass", "/bodies/0/position/2", "/bodies/1/velocity/0", "/effects/0/stiffness",
           "/effects/0/rest_length", "/effects/0/damping", "/effects/0/points/0/2", "/effects/1/points/1/0",
           "/effects/1/points/1/2", "/effects/1/stiffness", "/effects/1/rest_length", "/effects/2/acceleration/2"},
          {"p.z", "q.x", "q.vz", "energy"}};
}

// A compound pendulum (a rigid plate pinned to the world off its centre) carrying a particle on a distance
// constraint, with separate damping effects on the plate (linear and angular) and on the particle.
GradientScene Damping() {
  const double angle = 0.4, omega = -1.5;
  const Vec3<double> pivot = V(0.0, 0.0), hinge = V(-0.3, 0.1);  // hinge: the pinned point in the plate
  const Vec3<double> centre = pivot - RotatePlanar(angle, hinge);
  const Vec3<double> velocity = PointVelocity(Vec3<double>::Zero(), omega, centre - pivot);
  const Vec3<double> mount = V(0.2, -0.05), bead = centre + RotatePlanar(angle, mount) + V(0.1, -0.35);
  json d = {
      {"dimension", 2},
      {"bodies",
       {{{"name", "plate"}, {"type", "rigid"}, {"mass", 1.5}, {"inertia", 0.05}, {"position", Point(centre)},
         {"angle", angle}, {"velocity", Point(velocity)}, {"angular_velocity", omega}},
        {{"name", "bead"}, {"type", "particle"}, {"mass", 0.3}, {"position", Point(bead)}}}},
      {"constraints",
       {{{"type", "pin"}, {"bodies", {"world", "plate"}}, {"points", {Point(pivot), Point(hinge)}}},
        {{"type", "distance"}, {"bodies", {"plate", "bead"}}, {"points", {Point(mount), {0.0, 0.0}}},
         {"length", (V(0.1, -0.35)).norm()}}}},
      {"effects",
       {{{"type", "gravity"}, {"acceleration", {0.0, -9.81}}},
        {{"type", "damping"}, {"coefficient", 0.6}, {"angular_coefficient", 0.08}, {"bodies", {"plate"}}},
        {{"type", "damping"}, {"coefficient", 0.9}, {"bodies", {"bead"}}}}}};
  return {"Damping", d,
          {"/bodies/0/mass", "/bodies/0/inertia", "/bodies/0/angular_velocity", "/bodies/1/mass",
           "/constraints/0/points/1/0", "/constraints/1/points/0/1", "/constraints/1/length",
           "/effects/0/acceleration/1", "/effects/1/coefficient", "/effects/1/angular_coefficient",
           "/effects/2/coefficient"},
          {"plate.angle", "bead.y", "plate.omega", "bead.vx", "energy"}};
}

const char* IntegratorName(Integrator i) {
  const char* names[] = {"euler", "symplectic_euler", "rk4", "rk45"};
  return names[static_cast<int>(i)];
}
const char* StabilizationName(Stabilization s) {
  const char* names[] = {"none", "baumgarte", "projection"};
  return names[static_cast<int>(s)];
}

// The scene's document with its simulation and stabilization settings; gains are written out (and become
// parameters) under Baumgarte only, where they apply.
json Configured(const GradientScene& scene, Integrator integrator, Stabilization stabilization,
                std::vector<std::string>* parameters) {
  json d = scene.document;
  d["simulation"] = {{"integrator", IntegratorName(integrator)}, {"step", kStep}, {"duration", kDuration},
                     {"tolerance", kRk45Tolerance}};
  d["stabilization"] = {{"method", StabilizationName(stabilization)}};
  *parameters = scene.parameters;
  if (stabilization == Stabilization::kBaumgarte) {
    d["stabilization"]["alpha"] = kAlpha;
    d["stabilization"]["beta"] = kBeta;
    parameters->push_back("/stabilization/alpha");
    parameters->push_back("/stabilization/beta");
  }
  return d;
}

// ---------------------------------------------------------------------------------------------------------------
// observations

// A scratch file removed at the end of its scope.
class ScratchFile {
 public:
  explicit ScratchFile(const std::string& name) : path_(folder_.Path(name)) {}
  const std::string& path() const { return path_; }

 private:
  ::tether::testing::TempFolder folder_{"tether_gradient"};
  std::string path_;
};

// Simulates `truth` with stops at `times` and writes its `columns` there as an observation CSV, rows in reverse
// time order (the reader sorts them); the cell (gap_row, gap_column) is left empty when gap_row >= 0.
void WriteObservations(const Model<double>& truth, const std::vector<double>& times,
                       const std::vector<std::string>& columns, const std::string& path, int gap_row = -1,
                       int gap_column = -1) {
  std::stringstream in(tether::testing::TrajectoryCsvAt(truth, times));
  std::string line;
  std::getline(in, line);
  const std::vector<std::string> header = CsvCells(line);
  std::vector<size_t> picked = {0};  // t
  for (const std::string& name : columns) {
    for (size_t c = 0; c < header.size(); ++c) {
      if (header[c] == name) picked.push_back(c);
    }
  }
  ASSERT_EQ(picked.size(), columns.size() + 1) << "a column is not in the trajectory CSV";
  std::vector<std::string> rows;
  for (int row = 0; std::getline(in, line); ++row) {
    const std::vector<std::string> cells = CsvCells(line);
    std::string out;
    for (size_t k = 0; k < picked.size(); ++k) {
      const bool gap = row == gap_row && static_cast<int>(k) == gap_column + 1;
      out += (k ? "," : "") + (gap ? std::string() : cells[picked[k]]);
    }
    rows.push_back(out);
  }
  ASSERT_EQ(rows.size(), times.size());
  std::ofstream file(path);
  file << "t";
  for (const std::string& name : columns) file << "," << name;
  file << "\n";
  for (auto it = rows.rbegin(); it != rows.rend(); ++it) file << *it << "\n";
}

// The truth: every parameter moved by 3% of its size (alternating in sign).
Model<double> Truth(const json& document, const std::vector<std::string>& parameters) {
  json d = document;
  for (size_t i = 0; i < parameters.size(); ++i) {
    const json::json_pointer at(parameters[i]);
    const double value = d.at(at).get<double>();
    d[at] = value + (i % 2 ? -0.03 : 0.03) * std::max(std::abs(value), kSmallestSize);
  }
  return ParseScene(d, "truth.json").model;
}

// ---------------------------------------------------------------------------------------------------------------
// the reference gradient

double Loss(const Model<double>& model, const Observations& observations) {
  return 0.5 * ObservationResiduals(model, observations).squaredNorm();
}

struct Reference {
  std::vector<double> gradient;
  std::vector<double> spread;  // |difference of the last two Richardson levels|: the reference's own accuracy
};

// Central differences at h, h/2, h/4 with two levels of Richardson extrapolation.
Reference RichardsonGradient(const Model<double>& model, const ParameterSet& parameters,
                             const Observations& observations) {
  Reference out;
  const std::vector<double> values = parameters.Values(model);
  for (int i = 0; i < parameters.size(); ++i) {
    Model<double> shifted = model;
    auto central = [&](double h) {
      parameters.Field(&shifted, i) = values[i] + h;
      const double up = Loss(shifted, observations);
      parameters.Field(&shifted, i) = values[i] - h;
      const double down = Loss(shifted, observations);
      return (up - down) / (2 * h);
    };
    const double h = kRelativeStep * std::max(std::abs(values[i]), kSmallestSize);
    const double d1 = central(h), d2 = central(h / 2), d4 = central(h / 4);
    const double r1 = (4 * d2 - d1) / 3, r2 = (4 * d4 - d2) / 3;
    out.gradient.push_back((16 * r2 - r1) / 15);
    out.spread.push_back(std::abs(r2 - r1) / 15);
  }
  return out;
}

// Observations of `scene` made from its truth, read back against the nominal model.
struct Problem {
  Scene scene;
  ParameterSet parameters;
  Observations observations;
};

Problem MakeProblem(const json& document, const std::vector<std::string>& pointers,
                    const std::vector<std::string>& columns, const std::string& csv_path) {
  Problem p;
  p.scene = ParseScene(document, "gradient_scene.json");
  p.parameters = ParameterSet(p.scene, pointers);
  WriteObservations(Truth(document, pointers), kTimes, columns, csv_path, /*gap_row=*/1, /*gap_column=*/0);
  p.observations = ReadObservations(csv_path, p.scene.model);
  return p;
}

double Largest(const std::vector<double>& x) {
  double m = 0.0;
  for (double v : x) m = std::max(m, std::abs(v));
  return m;
}

// ---------------------------------------------------------------------------------------------------------------
// Jet gradients vs central differences, every scene x integrator x stabilization

enum class SceneKind { kParticles, kRigidPins, kSlider, kSprings, kDamping };
GradientScene Make(SceneKind kind) {
  switch (kind) {
    case SceneKind::kParticles: return Particles();
    case SceneKind::kRigidPins: return RigidPins();
    case SceneKind::kSlider: return Slider();
    case SceneKind::kSprings: return Springs();
    case SceneKind::kDamping: return Damping();
  }
  return Particles();
}

using Combination = std::tuple<SceneKind, Integrator, Stabilization>;

// Every scene kind with every integrator and stabilization.
auto AllCombinations() {
  return ::testing::Combine(::testing::Values(SceneKind::kParticles, SceneKind::kRigidPins, SceneKind::kSlider,
                                              SceneKind::kSprings, SceneKind::kDamping),
                            ::testing::Values(Integrator::kEuler, Integrator::kSymplecticEuler, Integrator::kRk4,
                                              Integrator::kRk45),
                            ::testing::Values(Stabilization::kNone, Stabilization::kBaumgarte,
                                              Stabilization::kProjection));
}

// A combination's scene (*scene) configured, its observations written to `csv` and read back, its parameters
// in *pointers.
Problem CombinationProblem(const Combination& combination, const ScratchFile& csv, GradientScene* scene,
                           std::vector<std::string>* pointers) {
  const auto [kind, integrator, stabilization] = combination;
  *scene = Make(kind);
  const json document = Configured(*scene, integrator, stabilization, pointers);
  return MakeProblem(document, *pointers, scene->columns, csv.path());
}

class JetGradient : public ::testing::TestWithParam<Combination> {};

TEST_P(JetGradient, MatchesRichardsonCentralDifferences) {
  GradientScene scene;
  std::vector<std::string> pointers;
  ScratchFile csv("observations.csv");
  const Problem p = CombinationProblem(GetParam(), csv, &scene, &pointers);
  ASSERT_EQ(p.observations.times, kTimes);
  ASSERT_EQ(p.observations.CellCount(), static_cast<int>(kTimes.size() * scene.columns.size()) - 1);  // one gap

  const LossGradient jet = JetLossGradient(p.scene.model, p.parameters, p.observations);
  const Reference reference = RichardsonGradient(p.scene.model, p.parameters, p.observations);
  ASSERT_EQ(jet.gradient.size(), pointers.size());

  // the value part: the loss of a double run, to round-off
  const double loss = Loss(p.scene.model, p.observations);
  EXPECT_GT(loss, 1e-8);  // the truth differs visibly from the nominal scene
  EXPECT_NEAR(jet.loss, loss, 1e-12 * loss);

  const double scale = Largest(reference.gradient);
  ASSERT_GT(scale, 0.0);
  for (size_t i = 0; i < pointers.size(); ++i) {
    const double g = reference.gradient[i];
    const double tolerance = kAgreement * std::max(1e-3 * scale, std::abs(g));
    EXPECT_NEAR(jet.gradient[i], g, tolerance)
        << pointers[i] << " (reference accurate to about " << reference.spread[i] << ", scale " << scale << ")";
    // every parameter matters, so that the comparison is not one of zeros (the gains barely do for the
    // high-order integrators, whose constraint drift is tiny)
    const bool gain = pointers[i].rfind("/stabilization/", 0) == 0;
    if (!gain) EXPECT_GT(std::abs(g), 1e-4 * scale) << pointers[i] << " barely changes the loss";
  }
}

std::string CombinationName(const ::testing::TestParamInfo<Combination>& info) {
  const auto [kind, integrator, stabilization] = info.param;
  const char* integrators[] = {"Euler", "SymplecticEuler", "Rk4", "Rk45"};
  const char* stabilizations[] = {"None", "Baumgarte", "Projection"};
  return Make(kind).name + "_" + integrators[static_cast<int>(integrator)] + "_" +
         stabilizations[static_cast<int>(stabilization)];
}

INSTANTIATE_TEST_SUITE_P(AllScenesIntegratorsAndStabilizations, JetGradient, AllCombinations(), CombinationName);


// ---------------------------------------------------------------------------------------------------------------
// the discrete adjoint vs Jets, every scene x integrator x stabilization

// Both differentiate the same computation (the adjoint in reverse), so they agree to round-off: 1e-8 relative to
// max(|g|, 1e-3 of the largest component).
constexpr double kAdjointAgreement = 1e-8;

// The adjoint's gradient against the Jets' to kAdjointAgreement; `where` adds to the messages.
void ExpectAdjointAgrees(const LossGradient& adjoint, const LossGradient& jet, const std::vector<std::string>& pointers,
                         const std::string& where = "") {
  const double scale = Largest(jet.gradient);
  ASSERT_GT(scale, 0.0);
  for (size_t i = 0; i < pointers.size(); ++i) {
    EXPECT_NEAR(adjoint.gradient[i], jet.gradient[i],
                kAdjointAgreement * std::max(1e-3 * scale, std::abs(jet.gradient[i])))
        << pointers[i] << where;
  }
}

class AdjointGradient : public ::testing::TestWithParam<Combination> {};

TEST_P(AdjointGradient, EqualsJets) {
  GradientScene scene;
  std::vector<std::string> pointers;
  ScratchFile csv("observations.csv");
  const Problem p = CombinationProblem(GetParam(), csv, &scene, &pointers);
  const LossGradient jet = JetLossGradient(p.scene.model, p.parameters, p.observations);
  AdjointReport report;
  const LossGradient adjoint = AdjointLossGradient(p.scene.model, p.parameters, p.observations, 0, &report);
  EXPECT_NEAR(adjoint.loss, jet.loss, 1e-12 * jet.loss);
  ASSERT_EQ(adjoint.gradient.size(), pointers.size());
  ExpectAdjointAgrees(adjoint, jet, pointers);
  // 150 grid steps and two stops off the grid, whose states all fit in the memory budget: every one is kept
  EXPECT_EQ(report.steps, 152);
  EXPECT_EQ(report.interval, 1);
  EXPECT_EQ(report.checkpoints, 152);
  EXPECT_GT(report.largest_record, 0);
}

INSTANTIATE_TEST_SUITE_P(AllScenesIntegratorsAndStabilizations, AdjointGradient, AllCombinations(),
                         CombinationName);

// Checkpoints change only what is recomputed: every state kept (K = 1, the default here), checkpoints every
// ceil(sqrt(152)) = 13 steps, and a single checkpoint (K = all steps) give the same numbers, bit for bit; so do
// the replays that take the double run's KKT solves (kkt_log.h: all of them with every state kept) and those that
// solve again (a segment's last step).
TEST(AdjointCheckpoints, CheckpointedEqualsStored) {
  const GradientScene scene = RigidPins();
  std::vector<std::string> pointers;
  const json document = Configured(scene, Integrator::kRk45, Stabilization::kBaumgarte, &pointers);
  ScratchFile csv("observations.csv");
  const Problem p = MakeProblem(document, pointers, scene.columns, csv.path());
  AdjointReport stored_report, checkpointed_report, single_report;
  const LossGradient stored = AdjointLossGradient(p.scene.model, p.parameters, p.observations, 1, &stored_report);
  const LossGradient checkpointed =
      AdjointLossGradient(p.scene.model, p.parameters, p.observations, 13, &checkpointed_report);
  const LossGradient single = AdjointLossGradient(p.scene.model, p.parameters, p.observations, 1000, &single_report);
  EXPECT_EQ(stored_report.checkpoints, 152);
  EXPECT_EQ(checkpointed_report.checkpoints, 12);
  EXPECT_EQ(single_report.checkpoints, 1);
  // checkpoints and one segment's states and KKT solves: fewer kept with checkpoints than with every state
  EXPECT_LT(checkpointed_report.memory_bytes - checkpointed_report.largest_record * Tape::kBytesPerNode,
            stored_report.memory_bytes - stored_report.largest_record * Tape::kBytesPerNode);
  EXPECT_GT(checkpointed_report.kkt_solve_bytes, 0);
  EXPECT_LT(checkpointed_report.kkt_solve_bytes, stored_report.kkt_solve_bytes);
  for (size_t i = 0; i < pointers.size(); ++i) {
    EXPECT_EQ(checkpointed.gradient[i], stored.gradient[i]) << pointers[i];
    EXPECT_EQ(single.gradient[i], stored.gradient[i]) << pointers[i];
  }
  EXPECT_EQ(checkpointed.loss, stored.loss);
}

// Distance rows between particles go through their own recorded operation (distance_adjoint.cc), and a rod
// named twice makes every Schur matrix singular, so that the solver regularizes it (kkt_adjoint.cc's
// regularized term): a three-particle chain hanging from two world points, its first rod duplicated, every
// point a constant so that all rows take that path. Adjoint and Jets agree as everywhere else.
TEST(AdjointGradient, ParticleRodsAndARedundantRodEqualJets) {
  json d = {{"dimension", 2},
            {"bodies",
             {{{"name", "a"}, {"type", "particle"}, {"mass", 1.0}, {"position", {0.6, -0.8}}, {"velocity", {0.4, 0.3}}},
              {{"name", "b"}, {"type", "particle"}, {"mass", 0.5}, {"position", {1.2, -1.6}}},
              {{"name", "c"}, {"type", "particle"}, {"mass", 0.8}, {"position", {1.9, -1.2}}}}},
            {"constraints",
             {{{"type", "distance"}, {"bodies", {"world", "a"}}, {"length", 1.0}},
              {{"type", "distance"}, {"bodies", {"world", "a"}}, {"length", 1.0}},
              {{"type", "distance"}, {"bodies", {"a", "b"}}, {"length", 1.0}},
              {{"type", "distance"}, {"bodies", {"b", "c"}}, {"length", (V(1.9, -1.2) - V(1.2, -1.6)).norm()}}}},
            {"effects", {{{"type", "gravity"}, {"acceleration", {0.0, -9.81}}}}}};
  const std::vector<std::string> pointers = {"/bodies/0/mass", "/bodies/2/mass", "/constraints/2/length",
                                             "/constraints/3/length", "/bodies/0/velocity/0",
                                             "/effects/0/acceleration/1"};
  for (const Integrator integrator : {Integrator::kRk4, Integrator::kRk45}) {
    for (const Stabilization stabilization : {Stabilization::kBaumgarte, Stabilization::kProjection}) {
      std::vector<std::string> unused;
      const json document = Configured({"RedundantRod", d, pointers, {}}, integrator, stabilization, &unused);
      ScratchFile csv("observations.csv");
      const Problem p = MakeProblem(document, pointers, {"b.x", "c.y", "c.vx"}, csv.path());
      const LossGradient jet = JetLossGradient(p.scene.model, p.parameters, p.observations);
      const LossGradient adjoint = AdjointLossGradient(p.scene.model, p.parameters, p.observations);
      ExpectAdjointAgrees(adjoint, jet, pointers,
                          " " + std::string(IntegratorName(integrator)) + " " + StabilizationName(stabilization));
    }
  }
}

// A four-bar (a parallelogram of 1 m, 1 kg bars, IFToMM A02 with N = 1) with the default gains through four
// horizontal passes, three of whose steps are retaken in substeps with the KKT solver's pivot floor
// (schur_solver.h, "Singular passes"): the adjoint's replay retakes the same steps (the KKT log carries the
// solver's conditioning) and equals the Jets.
TEST(AdjointGradient, ThroughTheRetakenStepsOfSingularPassesEqualsJets) {
  json bodies = json::array(), constraints = json::array();
  for (int i = 0; i < 2; ++i) {
    bodies.push_back({{"name", "crank" + std::to_string(i)},
                      {"type", "rigid"},
                      {"mass", 1.0},
                      {"inertia", 1.0 / 12.0},
                      {"position", {1.0 * i, 0.5}},
                      {"angle", M_PI / 2},
                      {"velocity", {0.5, 0.0}},
                      {"angular_velocity", -1.0}});
    constraints.push_back({{"type", "pin"},
                           {"bodies", {"world", "crank" + std::to_string(i)}},
                           {"points", {{1.0 * i, 0.0}, {-0.5, 0.0}}}});
    constraints.push_back({{"type", "pin"},
                           {"bodies", {"coupler", "crank" + std::to_string(i)}},
                           {"points", {{i - 0.5, 0.0}, {0.5, 0.0}}}});
  }
  bodies.push_back({{"name", "coupler"},
                    {"type", "rigid"},
                    {"mass", 1.0},
                    {"inertia", 1.0 / 12.0},
                    {"position", {0.5, 1.0}},
                    {"angle", 0.0},
                    {"velocity", {1.0, 0.0}},
                    {"angular_velocity", 0.0}});
  const json document = {{"dimension", 2},
                         {"bodies", bodies},
                         {"constraints", constraints},
                         {"effects", {{{"type", "gravity"}, {"acceleration", {0.0, -9.81}}}}},
                         {"simulation", {{"integrator", "rk4"}, {"step", 1e-3}, {"duration", 5.0}}}};
  const std::vector<std::string> pointers = {"/bodies/0/mass", "/bodies/2/inertia", "/effects/0/acceleration/1"};
  const Model<double> truth = Truth(document, pointers);
  ASSERT_GT(Simulate<double>(ParseScene(document, "four_bar.json").model, RunOptions{}, [](const Sample<double>&) {})
                .retaken_steps,
            0);
  ScratchFile csv("observations.csv");
  WriteObservations(truth, {1.0, 2.0, 3.0, 4.0, 5.0}, {"crank0.x", "coupler.y", "crank1.omega"}, csv.path(), 1, 0);
  const Scene scene = ParseScene(document, "four_bar.json");
  const ParameterSet parameters(scene, pointers);
  const Observations observations = ReadObservations(csv.path(), scene.model);
  const LossGradient jet = JetLossGradient(scene.model, parameters, observations);
  const LossGradient adjoint = AdjointLossGradient(scene.model, parameters, observations);
  ExpectAdjointAgrees(adjoint, jet, pointers);
}

// The memory rule: every state while they fit, then the smallest K with N / K + K states fitting, then sqrt(N).
TEST(AdjointCheckpoints, IntervalKeepsWithinTheBudget) {
  EXPECT_EQ(CheckpointInterval(1000, 8, 8000), 1);          // 1000 states fit
  const std::int64_t k = CheckpointInterval(1000000, 8, 8 * 10000);  // 10^4 states: K + 10^6 / K <= 10^4
  EXPECT_LE(k + (1000000 + k - 1) / k, 10000);
  EXPECT_GT((k - 1) + (1000000 + k - 2) / (k - 1), 10000);  // and K is the smallest such
  EXPECT_EQ(CheckpointInterval(1000000, 8, 8 * 100), 1000);  // nothing fits: 2 sqrt(N) states, the fewest
}

// A run whose fewest checkpoints, one segment and a step's record exceed the budget is refused before it runs,
// naming what it would need (it used to go past the budget: a 2000-link chain kept 330 MiB).
TEST(AdjointCheckpoints, ARunTheBudgetCannotHoldIsRefusedUpFront) {
  std::string bodies, constraints;
  for (int k = 0; k < 1000; ++k) {
    const std::string name = "\"p" + std::to_string(k) + "\"";
    bodies += std::string(k ? "," : "") + "{\"name\": " + name + ", \"type\": \"particle\", \"mass\": 0.001, " +
              "\"position\": [0, " + std::to_string(-0.001 * (k + 1)) + "]}";
    constraints += std::string(k ? "," : "") + "{\"type\": \"distance\", \"bodies\": [" +
                   (k ? "\"p" + std::to_string(k - 1) + "\"" : std::string("\"world\"")) + ", " + name + "]}";
  }
  // 10^8 steps of 32 kB states: 2 10^4 states are 640 MB
  const std::string text = R"({"dimension": 2, "bodies": [)" + bodies + R"(], "constraints": [)" + constraints +
                           R"(], "simulation": {"step": 1e-6, "duration": 100}})";
  const Scene scene = ParseScene(ParseJsonText(text, "chain.json"), "chain.json");
  const Model<double>& chain = scene.model;
  Observations observed;
  observed.columns = {{"p999.x", TrajectoryColumn::Kind::kConfiguration, 0}};
  observed.times = {100.0};
  observed.values = {{0.0}};
  observed.lines = {2};
  try {
    AdjointLossGradient(chain, ParameterSet(scene, {"/bodies/0/mass"}), observed);
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& e) {
    for (const char* part : {"cannot hold this run in its 256 MiB", "100000001 steps", "--method jet"})
      EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << part << " in: " << e.what();
  }
}

// ---------------------------------------------------------------------------------------------------------------
// the implicit-function KKT path vs the Jet-factorization oracle

// A hanging chain of `links` rigid bars on pins (2 rows each), in a generic zig-zag, the top bar turning.
GradientScene Chain(int links) {
  json bodies = json::array(), constraints = json::array();
  const double length = 0.3;
  Vec3<double> joint = V(0.0, 0.0);
  for (int k = 0; k < links; ++k) {
    const double angle = -1.2 + 0.35 * (k % 3) - 0.1 * k;
    const Vec3<double> centre = joint + RotatePlanar(angle, V(length / 2, 0.0));
    bodies.push_back({{"name", "link" + std::to_string(k)}, {"type", "rigid"}, {"mass", 0.5 + 0.05 * k},
                      {"inertia", 0.5 * length * length / 12}, {"position", Point(centre)}, {"angle", angle},
                      {"velocity", {0.0, 0.0}}, {"angular_velocity", 0.0}});
    const std::string above = k == 0 ? "world" : "link" + std::to_string(k - 1);
    constraints.push_back({{"type", "pin"}, {"bodies", {above, "link" + std::to_string(k)}},
                           {"points", {k == 0 ? Point(joint) : json{length / 2, 0.0}, {-length / 2, 0.0}}}});
    joint = joint + RotatePlanar(angle, V(length, 0.0));
  }
  bodies[0]["angular_velocity"] = 1.5;
  bodies[0]["velocity"] = Point(PointVelocity(Vec3<double>::Zero(), 1.5, RotatePlanar(-1.2, V(length / 2, 0.0))));
  json d = {{"dimension", 2},
            {"bodies", bodies},
            {"constraints", constraints},
            {"effects",
             {{{"type", "gravity"}, {"acceleration", {0.4, -9.81}}},
              {{"type", "damping"}, {"coefficient", 0.1}, {"angular_coefficient", 0.02}}}}};
  return {"Chain", d,
          {"/bodies/0/mass", "/bodies/4/inertia", "/bodies/0/angular_velocity", "/constraints/3/points/1/0",
           "/effects/0/acceleration/1", "/effects/1/angular_coefficient"},
          {"link0.angle", "link" + std::to_string(links - 1) + ".y", "link" + std::to_string(links / 2) + ".omega",
           "energy"}};
}

// The implicit function theorem applied to the factorization of the value part equals factoring the Jet matrix
// itself, to round-off: 1e-10 relative to max(|g|, 1e-3 of the largest component). The scenes start on their
// constraints, so the assembly's projections solve with right-hand sides whose values are exactly zero but whose
// derivatives are not (a Jet compares by its value only, so a solve that skips "zero" entries loses them).
void ExpectOracleAgreement(const GradientScene& scene, Stabilization stabilization, KktSolver path) {
  std::vector<std::string> pointers;
  json document = Configured(scene, Integrator::kRk4, stabilization, &pointers);
  document["simulation"]["solver"] = path == KktSolver::kDense ? "dense" : "sparse";
  ScratchFile csv("observations.csv");
  const Problem p = MakeProblem(document, pointers, scene.columns, csv.path());
  ASSERT_EQ(p.scene.model.simulation.solver, path);
  const LossGradient ift = JetLossGradient(p.scene.model, p.parameters, p.observations);
  const LossGradient oracle = JetLossGradient(p.scene.model, p.parameters, p.observations, true);
  EXPECT_NEAR(ift.loss, oracle.loss, 1e-13 * oracle.loss);
  const double scale = Largest(oracle.gradient);
  ASSERT_GT(scale, 0.0);
  for (size_t i = 0; i < pointers.size(); ++i) {
    EXPECT_NEAR(ift.gradient[i], oracle.gradient[i], 1e-10 * std::max(1e-3 * scale, std::abs(oracle.gradient[i])))
        << pointers[i];
  }
}

TEST(JetGradientOracle, DensePathEqualsFactoringJets) {
  for (Stabilization s : {Stabilization::kBaumgarte, Stabilization::kProjection}) {
    SCOPED_TRACE(StabilizationName(s));
    ExpectOracleAgreement(RigidPins(), s, KktSolver::kDense);
  }
}

TEST(JetGradientOracle, SparsePathEqualsFactoringJets) {
  const GradientScene chain = Chain(9);  // 18 rows
  for (Stabilization s : {Stabilization::kBaumgarte, Stabilization::kProjection}) {
    SCOPED_TRACE(StabilizationName(s));
    ExpectOracleAgreement(chain, s, KktSolver::kSparse);
  }
}

// The smallest case of the two tests above: observations at t = 0 only, so the loss depends on the parameters
// only through the assembly of the initial state (a Gauss-Newton projection whose last iteration, and the
// velocity projection, solve with right-hand sides whose values are exactly zero for this consistent state).
// Both Jet paths must give the central-difference gradient.
TEST(JetGradientOracle, BothPathsThroughTheInitialAssembly) {
  const GradientScene scene = Particles();
  std::vector<std::string> pointers;
  const json document = Configured(scene, Integrator::kRk4, Stabilization::kBaumgarte, &pointers);
  pointers = {"/bodies/0/position/0", "/bodies/1/position/1", "/bodies/0/velocity/1", "/constraints/1/length"};
  const Scene nominal = ParseScene(document, "particles.json");
  const ParameterSet parameters(nominal, pointers);
  ScratchFile csv("observations.csv");
  WriteObservations(Truth(document, pointers), {0.0}, {"b.x", "b.y", "b.vx", "b.vy"}, csv.path());
  const Observations observations = ReadObservations(csv.path(), nominal.model);
  const Reference reference = RichardsonGradient(nominal.model, parameters, observations);
  const LossGradient ift = JetLossGradient(nominal.model, parameters, observations);
  const LossGradient oracle = JetLossGradient(nominal.model, parameters, observations, true);
  const double scale = Largest(reference.gradient);
  ASSERT_GT(scale, 0.0);
  for (size_t i = 0; i < pointers.size(); ++i) {
    const double g = reference.gradient[i];
    const double tolerance = kAgreement * std::max(1e-3 * scale, std::abs(g));
    EXPECT_NEAR(ift.gradient[i], g, tolerance) << "implicit function theorem, " << pointers[i];
    EXPECT_NEAR(oracle.gradient[i], g, tolerance) << "factoring Jets, " << pointers[i];
  }
}

// The chain's Jet gradient also matches central differences (the sparse path is not only self-consistent).
TEST(JetGradientOracle, SparsePathMatchesCentralDifferences) {
  const GradientScene chain = Chain(9);
  std::vector<std::string> pointers;
  const json document = Configured(chain, Integrator::kRk4, Stabilization::kBaumgarte, &pointers);
  ScratchFile csv("observations.csv");
  const Problem p = MakeProblem(document, pointers, chain.columns, csv.path());
  const LossGradient jet = JetLossGradient(p.scene.model, p.parameters, p.observations);
  const Reference reference = RichardsonGradient(p.scene.model, p.parameters, p.observations);
  const double scale = Largest(reference.gradient);
  for (size_t i = 0; i < pointers.size(); ++i) {
    const double g = reference.gradient[i];
    EXPECT_NEAR(jet.gradient[i], g, kAgreement * std::max(1e-3 * scale, std::abs(g))) << pointers[i];
  }
}

// ---------------------------------------------------------------------------------------------------------------
// chunks of kJetStride

TEST(JetGradientChunks, NineParametersAtOnceEqualOneByOne) {
  const GradientScene scene = Particles();
  std::vector<std::string> pointers;
  const json document = Configured(scene, Integrator::kRk4, Stabilization::kBaumgarte, &pointers);
  pointers.resize(9);  // ceil(9 / kJetStride) = 3 chunks, the last one partial
  ASSERT_GT(static_cast<int>(pointers.size()), 2 * kJetStride);
  ScratchFile csv("observations.csv");
  const Problem p = MakeProblem(document, pointers, scene.columns, csv.path());
  const LossGradient all = JetLossGradient(p.scene.model, p.parameters, p.observations);
  ASSERT_EQ(all.gradient.size(), 9u);
  for (size_t i = 0; i < pointers.size(); ++i) {
    const ParameterSet one(p.scene, {pointers[i]});
    const LossGradient single = JetLossGradient(p.scene.model, one, p.observations);
    ASSERT_EQ(single.gradient.size(), 1u);
    EXPECT_NE(single.gradient[0], 0.0) << pointers[i];
    // the same arithmetic per derivative direction: equal to round-off
    EXPECT_NEAR(all.gradient[i], single.gradient[0], 1e-12 * std::abs(single.gradient[0])) << pointers[i];
    EXPECT_NEAR(all.loss, single.loss, 1e-14 * single.loss);
  }
}

// ---------------------------------------------------------------------------------------------------------------
// the loss, computed independently

TEST(LossGradient, LossIsHalfTheSumOfSquaresOfAPlainRun) {
  // the particle double pendulum under rk4; observations on the grid, values made up
  std::vector<std::string> pointers;
  const json document = Configured(Particles(), Integrator::kRk4, Stabilization::kBaumgarte, &pointers);
  const Scene scene = ParseScene(document, "particles.json");
  const std::vector<double> times = {0.0, 0.05, 0.1, 0.2, kDuration};
  ScratchFile csv("observations.csv");
  {
    std::ofstream file(csv.path());
    file << "t,b.y,a.vx,energy,a.x\n";
    for (size_t k = 0; k < times.size(); ++k) {
      file << times[k] << "," << -0.9 + 0.01 * k << "," << 0.1 * k << "," << (k == 2 ? "" : "-3.5") << ","
           << 0.5 - 0.02 * k << "\n";
    }
  }
  const Observations observations = ReadObservations(csv.path(), scene.model);
  const ParameterSet parameters(scene, {"/bodies/0/mass", "/effects/1/coefficient"});

  // a plain run on the grid, every step output; q = (a.x, a.y, b.x, b.y), v likewise
  double expected = 0.0;
  int matched = 0;
  RunOptions run;
  run.every = 1;
  Simulate<double>(scene.model, run, [&](const Sample<double>& s) {
    for (size_t k = 0; k < times.size(); ++k) {
      if (std::abs(s.t - times[k]) > 1e-12) continue;
      ++matched;
      const double dy = s.q[3] - (-0.9 + 0.01 * k), dvx = s.v[0] - 0.1 * k, dx = s.q[0] - (0.5 - 0.02 * k);
      expected += 0.5 * (dy * dy + dvx * dvx + dx * dx);
      if (k != 2) expected += 0.5 * (s.energy + 3.5) * (s.energy + 3.5);
    }
  });
  ASSERT_EQ(matched, static_cast<int>(times.size()));
  ASSERT_GT(expected, 0.1);
  // the stops on the grid are served by the grid steps: the same states to round-off
  EXPECT_NEAR(JetLossGradient(scene.model, parameters, observations).loss, expected, 1e-12 * expected);
  EXPECT_NEAR(CentralDifferenceLossGradient(scene.model, parameters, observations).loss, expected, 1e-12 * expected);
  EXPECT_NEAR(Loss(scene.model, observations), expected, 1e-12 * expected);
}

// ---------------------------------------------------------------------------------------------------------------
// stop times

TEST(Stops, OffGridStopsAreSampledExactlyThere) {
  std::vector<std::string> pointers;
  const json document = Configured(Particles(), Integrator::kRk4, Stabilization::kBaumgarte, &pointers);
  const Model<double> model = ParseScene(document, "particles.json").model;
  RunOptions run;
  run.every = 25;
  run.stops = {0.0, 0.0371, 0.1234, 0.2, 0.2777, kDuration};
  std::vector<double> stop_times;
  std::vector<int> stop_indices;
  std::vector<VecX<double>> stop_q;
  std::vector<double> output_times;
  Simulate<double>(model, run, [&](const Sample<double>& s) {
    if (s.stop >= 0) {
      stop_indices.push_back(s.stop);
      stop_times.push_back(s.t);
      stop_q.push_back(s.q);
    }
    if (s.output) output_times.push_back(s.t);
  });
  ASSERT_EQ(stop_indices, (std::vector<int>{0, 1, 2, 3, 4, 5}));  // each stop once, in order
  EXPECT_EQ(stop_times, run.stops);                                // exactly the requested times
  // output rows stay on the grid (every 25th step of 2e-3 s, and the last)
  ASSERT_EQ(output_times.size(), 7u);
  for (size_t k = 0; k < output_times.size(); ++k) EXPECT_NEAR(output_times[k], 0.05 * k, 1e-12);

  // the state at 0.1234 s is the state there, not at a neighbouring grid time: a run whose grid contains
  // 0.1234 (h = 1e-4) agrees to rk4's accuracy (error ~ h^4, here below 1e-9 m), while the grid times 0.122 and
  // 0.124 are millimetres away
  Model<double> fine = model;
  fine.simulation.step = 1e-4;
  fine.simulation.duration = 0.1234;
  VecX<double> last;
  RunOptions plain;
  Simulate<double>(fine, plain, [&last](const Sample<double>& s) { last = s.q; });
  EXPECT_LT((stop_q[2] - last).cwiseAbs().maxCoeff(), 1e-9);
}

}  // namespace
}  // namespace tether
