#include "bench_models.h"

#include <cmath>
#include <string>
#include <vector>

#include "tether/dynamics/integration/default_gains.h"
#include "tether/dynamics/integration/integrators.h"

namespace tether::bench {
namespace {

void Connect(Model<double>* model, JointType type, int a, const Vec3<double>& on_a, int b, const Vec3<double>& on_b,
             double length = 1.0) {
  Joint<double> joint;
  joint.scene_index = model->NumConstraints();
  joint.type = type;
  joint.a = {a, on_a};
  joint.b = {b, on_b};
  joint.length = length;
  AddJoint(model, joint);
}

}  // namespace

void SetGains(Model<double>* model, double alpha, double beta) {
  model->stabilization.method = Stabilization::kBaumgarte;
  model->stabilization.alpha = alpha;
  model->stabilization.beta = beta;
  model->stabilization.gains_from_rule = false;
}

Model<double> HorizontalChain(int n, Integrator integrator, KktSolver solver, int dimension) {
  Model<double> model;
  model.dimension = dimension;
  const double link = 1.0;
  for (int k = 0; k < n; ++k) {
    AddBody<double>(&model, "p" + std::to_string(k), BodyKind::kParticle, 1.0, 0.0, Vec3<double>((k + 1) * link, 0, 0),
                    0.0, Vec3<double>::Zero(), 0.0);
    Connect(&model, JointType::kDistance, k - 1, Vec3<double>::Zero(), k, Vec3<double>::Zero(), link);
  }
  model.gravity.push_back({0, -9.81 * Vec3<double>::Unit(dimension - 1)});
  model.simulation.integrator = integrator;
  model.simulation.solver = solver;
  SetGains(&model, 20.0, 100.0);
  return model;
}

nlohmann::json HorizontalChainScene(int n, double duration) {
  const double link = 1.0;
  nlohmann::json bodies = nlohmann::json::array(), constraints = nlohmann::json::array();
  for (int k = 0; k < n; ++k) {
    const std::string name = "p" + std::to_string(k);
    bodies.push_back({{"name", name}, {"type", "particle"}, {"mass", 1.0}, {"position", {(k + 1) * link, 0.0}}});
    constraints.push_back({{"type", "distance"},
                           {"bodies", {k == 0 ? std::string("world") : "p" + std::to_string(k - 1), name}},
                           {"length", link}});
  }
  return {{"dimension", 2},
          {"bodies", bodies},
          {"constraints", constraints},
          {"effects", nlohmann::json::array({{{"type", "gravity"}, {"acceleration", {0.0, -9.81}}}})},
          {"simulation", {{"integrator", "rk4"}, {"step", 1e-3}, {"duration", duration}}},
          {"stabilization", {{"method", "baumgarte"}, {"alpha", 20.0}, {"beta", 100.0}}}};
}

Model<double> BinaryTree(int n, KktSolver solver) {
  Model<double> model;
  std::vector<Vec3<double>> position;
  for (int k = 0; k < n; ++k) {
    const int parent = k == 0 ? kWorld : (k - 1) / 2;
    const double angle = k % 2 == 1 ? -0.4 : 0.8;  // from the downward vertical
    const Vec3<double> top = parent == kWorld ? Vec3<double>::Zero() : position[parent];
    position.push_back(top + Vec3<double>(std::sin(angle), -std::cos(angle), 0));
    AddBody<double>(&model, "p" + std::to_string(k), BodyKind::kParticle, 1.0, 0.0, position.back(), 0.0,
                    Vec3<double>::Zero(), 0.0);
    Connect(&model, JointType::kDistance, parent, Vec3<double>::Zero(), k, Vec3<double>::Zero());
  }
  model.gravity.push_back({0, Vec3<double>(0, -9.81, 0)});
  model.simulation.solver = solver;
  SetGains(&model, 20.0, 100.0);
  return model;
}

Model<double> FourBar(int n, KktSolver solver) {
  Model<double> model;
  const double inertia = 1.0 / 12.0;
  for (int i = 0; i <= n; ++i) {
    AddBody<double>(&model, "crank" + std::to_string(i), BodyKind::kPlanar, 1.0, inertia, Vec3<double>(i, 0.5, 0),
                    M_PI / 2, Vec3<double>(0.5, 0, 0), -1.0);
    Connect(&model, JointType::kPin, kWorld, Vec3<double>(i, 0, 0), i, Vec3<double>(-0.5, 0, 0));
  }
  for (int i = 0; i < n; ++i) {
    const int coupler = AddBody<double>(&model, "coupler" + std::to_string(i), BodyKind::kPlanar, 1.0, inertia,
                                        Vec3<double>(i + 0.5, 1.0, 0), 0.0, Vec3<double>(1.0, 0, 0), 0.0);
    Connect(&model, JointType::kPin, coupler, Vec3<double>(-0.5, 0, 0), i, Vec3<double>(0.5, 0, 0));
    Connect(&model, JointType::kPin, coupler, Vec3<double>(0.5, 0, 0), i + 1, Vec3<double>(0.5, 0, 0));
  }
  model.gravity.push_back({0, Vec3<double>(0, -9.81, 0)});
  model.simulation.solver = solver;
  return model;
}

Vec3<double> RodInertia(double mass, double length) {
  const double radius = 0.02;
  const double transverse = mass * (3 * radius * radius + length * length) / 12;
  return Vec3<double>(0.5 * mass * radius * radius, transverse, transverse);
}

Model<double> HingeChain(int n, Integrator integrator, KktSolver solver) {
  Model<double> model;
  model.dimension = 3;
  for (int k = 0; k < n; ++k) {
    AddRigidBody3d<double>(&model, "l" + std::to_string(k), 1.0, RodInertia(1.0, 1.0).asDiagonal(),
                           Vec3<double>(k + 0.5, 0, 0), Vec4<double>(1, 0, 0, 0), Vec3<double>::Zero(),
                           Vec3<double>::Zero());
    Connect(&model, JointType::kHinge, k - 1, Vec3<double>(k == 0 ? 0.0 : 0.5, 0, 0), k, Vec3<double>(-0.5, 0, 0));
    model.joints.back().axis = Vec3<double>::UnitY();
  }
  model.gravity.push_back({0, Vec3<double>(0, 0, -9.81)});
  model.simulation.integrator = integrator;
  model.simulation.solver = solver;
  SetGains(&model, 20.0, 100.0);
  return model;
}

Model<double> HingeTree(int n, KktSolver solver) {
  Model<double> model;
  model.dimension = 3;
  std::vector<Vec3<double>> tip;  // the lower end of each link
  for (int k = 0; k < n; ++k) {
    const int parent = k == 0 ? kWorld : (k - 1) / 2;
    const double angle = k % 2 == 1 ? -0.4 : 0.8;  // from the downward vertical, in the x-z plane
    const Vec3<double> top = parent == kWorld ? Vec3<double>::Zero() : tip[parent];
    const Vec3<double> along(std::sin(angle), 0, -std::cos(angle));
    tip.push_back(top + along);
    // body x along the link: a rotation about y by the angle that takes x to `along`
    const double turn = std::atan2(-along.z(), along.x());
    const Vec4<double> orientation(std::cos(turn / 2), 0, std::sin(turn / 2), 0);
    AddRigidBody3d<double>(&model, "l" + std::to_string(k), 1.0, RodInertia(1.0, 1.0).asDiagonal(), top + 0.5 * along,
                           orientation, Vec3<double>::Zero(), Vec3<double>::Zero());
    Connect(&model, JointType::kHinge, parent, parent == kWorld ? Vec3<double>::Zero() : Vec3<double>(0.5, 0, 0), k,
            Vec3<double>(-0.5, 0, 0));
    model.joints.back().axis = Vec3<double>::UnitY();
  }
  model.gravity.push_back({0, Vec3<double>(0, 0, -9.81)});
  model.simulation.solver = solver;
  SetGains(&model, 20.0, 100.0);
  return model;
}

Model<double> Pendulum(Integrator integrator, double step) {
  Model<double> model;
  const double angle = M_PI / 3;
  AddBody<double>(&model, "bob", BodyKind::kParticle, 1.0, 0.0, Vec3<double>(std::sin(angle), -std::cos(angle), 0), 0.0,
                  Vec3<double>::Zero(), 0.0);
  Connect(&model, JointType::kDistance, kWorld, Vec3<double>::Zero(), 0, Vec3<double>::Zero());
  model.gravity.push_back({0, Vec3<double>(0, -9.81, 0)});
  model.simulation.integrator = integrator;
  model.simulation.step = step;
  return model;
}

constexpr int kStepsPerRun = 250;

void StepModel(benchmark::State& state, const Model<double>& model) {
  const State<double> start = InitialState(model);
  Workspace<double> ws(model, start.q);
  GainsInUse(model, &ws.alpha, &ws.beta);
  VecX<double> q = start.q, v = start.v;
  const double h = model.simulation.step;
  int step = 0;
  TimeIntegrator<double> integrator(model);
  for (auto _ : state) {
    if (step == kStepsPerRun) {
      state.PauseTiming();
      q = start.q;
      v = start.v;
      step = 0;
      state.ResumeTiming();
    }
    if (integrator.Advance(step * h, h, &ws, &q, &v) != StepStatus::kOk) {
      state.SkipWithError("a step failed");
      break;
    }
    ++step;
    benchmark::DoNotOptimize(q.data());
  }
  state.counters["rows"] = static_cast<double>(ws.infos.size());
  state.SetItemsProcessed(state.iterations());
}

}  // namespace tether::bench
