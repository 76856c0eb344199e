#include "bench_models.h"

#include <cmath>
#include <string>
#include <vector>

#include "tether/dynamics/default_gains.h"
#include "tether/dynamics/integrators.h"

namespace tether::bench {

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
    model.distances.push_back({k, BodyPoint<double>{k - 1}, BodyPoint<double>{k}, link});
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
    model.distances.push_back({k, BodyPoint<double>{parent}, BodyPoint<double>{k}, 1.0});
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
    AddBody<double>(&model, "crank" + std::to_string(i), BodyKind::kRigid, 1.0, inertia, Vec3<double>(i, 0.5, 0),
                    M_PI / 2, Vec3<double>(0.5, 0, 0), -1.0);
    model.pins.push_back({i, {kWorld, Vec3<double>(i, 0, 0)}, {i, Vec3<double>(-0.5, 0, 0)}});
  }
  for (int i = 0; i < n; ++i) {
    const int coupler = AddBody<double>(&model, "coupler" + std::to_string(i), BodyKind::kRigid, 1.0, inertia,
                                        Vec3<double>(i + 0.5, 1.0, 0), 0.0, Vec3<double>(1.0, 0, 0), 0.0);
    model.pins.push_back({n + 1 + 2 * i, {coupler, Vec3<double>(-0.5, 0, 0)}, {i, Vec3<double>(0.5, 0, 0)}});
    model.pins.push_back({n + 2 + 2 * i, {coupler, Vec3<double>(0.5, 0, 0)}, {i + 1, Vec3<double>(0.5, 0, 0)}});
  }
  model.gravity.push_back({0, Vec3<double>(0, -9.81, 0)});
  model.simulation.solver = solver;
  return model;
}

Model<double> Pendulum(Integrator integrator, double step) {
  Model<double> model;
  const double angle = M_PI / 3;
  AddBody<double>(&model, "bob", BodyKind::kParticle, 1.0, 0.0, Vec3<double>(std::sin(angle), -std::cos(angle), 0), 0.0,
                  Vec3<double>::Zero(), 0.0);
  model.distances.push_back({0, BodyPoint<double>{kWorld}, BodyPoint<double>{0}, 1.0});
  model.gravity.push_back({0, Vec3<double>(0, -9.81, 0)});
  model.simulation.integrator = integrator;
  model.simulation.step = step;
  return model;
}

constexpr int kStepsPerRun = 250;

void StepModel(benchmark::State& state, const Model<double>& model) {
  Workspace<double> ws(model);
  GainsInUse(model, &ws.alpha, &ws.beta);
  VecX<double> q = model.q0, v = model.v0;
  const double h = model.simulation.step;
  int step = 0;
  for (auto _ : state) {
    if (step == kStepsPerRun) {
      state.PauseTiming();
      q = model.q0;
      v = model.v0;
      step = 0;
      state.ResumeTiming();
    }
    if (Advance(model, step * h, h, &ws, &q, &v) != StepStatus::kOk) {
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
