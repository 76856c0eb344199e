// tether against MuJoCo on the same scenes, side by side in one run (issue 8; bench/peer/README.md). For each
// scene and integrator pair (tether symplectic_euler against MuJoCo's semi-implicit "Euler", rk4 against "RK4"),
// h = 1e-3, both engines first run once untimed, observing every step: the largest constraint violation and the
// largest energy error |E(t) - E(0)|, also as a fraction of the largest drop of potential energy. Then the same
// run, without observation, is timed; items are steps.
//
// tether runs Baumgarte stabilization with alpha = 100, beta = 2500: the error dynamics C'' + 100 C' + 2500 C = 0
// are MuJoCo's default solref (0.02, 1) (time constant 0.02 s, damping ratio 1) written as gains, so both engines
// pull drift back equally hard; tether solves the constraints exactly at the acceleration level, MuJoCo softly.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "mujoco_models.h"
#include "tether/dynamics/model.h"
#include "tether/dynamics/simulator.h"

namespace tether::bench {
namespace {

constexpr double kGravity = 9.81;
constexpr double kStep = 1e-3;

struct PeerCase {
  PeerScene scene;
  int n;  // the chain's particles
  bool rk4;
  double duration;
};

// What the untimed run observed.
struct Observed {
  double worst_violation = 0.0;
  double worst_energy_error = 0.0;
  double largest_potential_drop = 0.0;
  double Track(double violation, double energy, double potential, double energy0, double potential0) {
    worst_violation = std::max(worst_violation, violation);
    worst_energy_error = std::max(worst_energy_error, std::abs(energy - energy0));
    largest_potential_drop = std::max(largest_potential_drop, potential0 - potential);
    return 0.0;
  }
};

void Report(benchmark::State& state, const Observed& seen, int steps) {
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations()) * steps);
  state.counters["max_violation_m"] = seen.worst_violation;
  state.counters["energy_error_J"] = seen.worst_energy_error;
  state.counters["energy_error_of_drop"] = seen.worst_energy_error / std::max(seen.largest_potential_drop, 1e-300);
  state.counters["steps"] = steps;
}

int Steps(const PeerCase& c) { return static_cast<int>(std::lround(c.duration / kStep)); }

Model<double> TetherScene(const PeerCase& c) {
  Model<double> model;
  if (c.scene == PeerScene::kChain) {
    model.dimension = 3;
    for (int k = 0; k < c.n; ++k) {
      AddBody<double>(&model, "p" + std::to_string(k), BodyKind::kParticle, 1.0, 0.0, Vec3<double>(k + 1.0, 0, 0), 0.0,
                      Vec3<double>::Zero(), 0.0);
      model.distances.push_back({k, BodyPoint<double>{k - 1}, BodyPoint<double>{k}, 1.0});
    }
    model.gravity.push_back({0, Vec3<double>(0, 0, -kGravity)});
  } else {  // scenes/four_bar.json
    const double inertia = 1.0 / 12.0;
    for (int i = 0; i <= 1; ++i) {
      AddBody<double>(&model, "crank" + std::to_string(i), BodyKind::kRigid, 1.0, inertia, Vec3<double>(i, 0.5, 0),
                      M_PI / 2, Vec3<double>(0.5, 0, 0), -1.0);
      model.pins.push_back({i, {kWorld, Vec3<double>(i, 0, 0)}, {i, Vec3<double>(-0.5, 0, 0)}});
    }
    AddBody<double>(&model, "coupler", BodyKind::kRigid, 1.0, inertia, Vec3<double>(0.5, 1.0, 0), 0.0,
                    Vec3<double>(1.0, 0, 0), 0.0);
    model.pins.push_back({2, {2, Vec3<double>(-0.5, 0, 0)}, {0, Vec3<double>(0.5, 0, 0)}});
    model.pins.push_back({3, {2, Vec3<double>(0.5, 0, 0)}, {1, Vec3<double>(0.5, 0, 0)}});
    model.gravity.push_back({0, Vec3<double>(0, -kGravity, 0)});
  }
  model.simulation.integrator = c.rk4 ? Integrator::kRk4 : Integrator::kSymplecticEuler;
  model.simulation.step = kStep;
  model.simulation.duration = c.duration;
  model.stabilization.method = Stabilization::kBaumgarte;
  model.stabilization.alpha = 100.0;
  model.stabilization.beta = 2500.0;
  model.stabilization.gains_from_rule = false;
  return model;
}

// m g height summed over the bodies (every mass is 1 kg; up is the last coordinate of a position)
double TetherPotential(const Model<double>& model, const VecX<double>& q) {
  double potential = 0.0;
  for (const Body<double>& body : model.bodies) potential += body.mass * kGravity * q[body.offset + model.dimension - 1];
  return potential;
}

void Tether(benchmark::State& state, PeerCase c) {
  const Model<double> model = TetherScene(c);
  Observed seen;
  double energy0 = 0.0, potential0 = 0.0;
  Simulate<double>(model, RunOptions{}, [&](const Sample<double>& s) {
    const double potential = TetherPotential(model, s.q);
    if (s.t == 0.0) {
      energy0 = s.energy;
      potential0 = potential;
    }
    seen.Track(s.constraint_error, s.energy, potential, energy0, potential0);
  });
  RunOptions quiet;
  quiet.every = Steps(c);
  for (auto _ : state) Simulate<double>(model, quiet, [](const Sample<double>& s) { benchmark::DoNotOptimize(s.q.data()); });
  Report(state, seen, Steps(c));
}

void Mujoco(benchmark::State& state, PeerCase c) {
  const MjModelPtr model = LoadMujoco(MujocoScene(c.scene, c.n, c.rk4));
  Observed seen;
  {
    const MjDataPtr data = InitialMujocoState(*model, c.scene);
    const double energy0 = data->energy[0] + data->energy[1], potential0 = data->energy[0];
    for (int k = 0; k < Steps(c); ++k) {
      mj_step(model.get(), data.get());
      mj_forward(model.get(), data.get());  // positions and energy of the state after the step
      seen.Track(MujocoViolation(*model, *data, c.scene), data->energy[0] + data->energy[1], data->energy[0], energy0,
                 potential0);
    }
  }
  for (auto _ : state) {
    state.PauseTiming();
    const MjDataPtr data = InitialMujocoState(*model, c.scene);
    state.ResumeTiming();
    for (int k = 0; k < Steps(c); ++k) mj_step(model.get(), data.get());
    benchmark::DoNotOptimize(data->qpos);
  }
  Report(state, seen, Steps(c));
}

void Register() {
  struct Named {
    std::string name;
    PeerCase c;
  };
  std::vector<Named> cases;
  for (bool rk4 : {false, true}) {
    const std::string integrator = rk4 ? "rk4" : "euler";
    for (int n : {10, 50, 200, 1000}) {
      cases.push_back({"chain" + std::to_string(n) + "/" + integrator, {PeerScene::kChain, n, rk4, n == 1000 ? 1.0 : 10.0}});
    }
    cases.push_back({"four_bar/" + integrator, {PeerScene::kFourBar, 0, rk4, 10.0}});
  }
  for (const Named& named : cases) {
    benchmark::RegisterBenchmark(("tether/" + named.name).c_str(), Tether, named.c)
        ->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1)->Repetitions(3)->ReportAggregatesOnly(false);
    benchmark::RegisterBenchmark(("mujoco/" + named.name).c_str(), Mujoco, named.c)
        ->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1)->Repetitions(3)->ReportAggregatesOnly(false);
  }
}

}  // namespace
}  // namespace tether::bench

int main(int argc, char** argv) {
  mju_user_warning = nullptr;
  tether::bench::Register();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
