// tether, MuJoCo and Simbody on the same scenes in one run (bench/peer/README.md, "Against Simbody"): the chaotic
// double pendulum (the hinge chain of two rods released horizontal, 5 s), the 10- and 200-rod hinge chains (5 s
// and 1 s), the humanoid-sized tree (5 s), the RSSR loop (3 s) and the IFToMM A02
// N-four-bar with ten parallelograms (21 bars, 5 s, five passes through its singular configuration). Each engine in
// its own terms (tether_models.h, mujoco_models.h, simbody_models.h):
//   tether/rk4          rk4, h = 1e-3, Baumgarte (100, 2500), as in peer_bench.cc
//   tether/rk45_TOL     rk45 with the projection stabilization at tolerance TOL = 1e-4, 1e-6, ..., 1e-12, one output
//                       at the end
//   mujoco/rk4          RK4, h = 1e-3, MuJoCo's default soft equality constraints
//   tether/rk4_hH, mujoco/rk4_hH   the same at h = H = 2e-3, 5e-4, 2.5e-4 (the work-precision diagrams of
//                       studies/accuracy/work_precision.py)
//   simbody/rkm_ACC     Runge-Kutta-Merson at accuracy ACC = 1e-4, 1e-6, ..., 1e-12 (constraint tolerance ACC / 10,
//                       projection on)
//   simbody/cpodes_ACC  CPodes (BDF, Newton iterations) at accuracy ACC = 1e-6, 1e-8
//
// Accuracy: the largest distance between a body's centre of mass at the end and the reference's, in metres. The
// reference of the N-four-bar is its exact one-degree-of-freedom motion (tests/n_four_bar_reduction.h). The
// other scenes' reference is Simbody's Runge-Kutta-Merson at accuracy 1e-12; tether's rk45 at 1e-12 runs beside it
// as an independent check of that reference (and of the two builds of each mechanism).
//
// Every benchmark first runs its scene once untimed, observing every step (Simbody: every internal step; tether's
// rk45: its start and its end only, which its projection keeps at rounding after every internal step): the largest
// violation of the engine's own constraints, and the state at the end. Then the
// same run, unobserved, is timed; one iteration is the whole run, so the time per simulated second is the time
// over the duration. tether's timed run includes its set-up; MuJoCo's excludes mj_makeData and the initial
// mj_forward; Simbody's excludes building the system, and includes the integrator's initialization.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "mujoco_models.h"
#include "n_four_bar_reduction.h"
#include "simbody_models.h"
#include "tether/dynamics/integration/simulator.h"
#include "tether/dynamics/model/errors.h"
#include "tether/dynamics/model/kinematics.h"
#include "tether_models.h"

namespace tether::bench {
namespace {

struct PeerScene {
  std::string name;
  Mechanism mechanism;
  int n;            // rods or parallelograms
  double duration;  // s
  MujocoScene mujoco;
};

const std::vector<PeerScene>& Scenes() {
  static const std::vector<PeerScene> scenes = {
      {"double_pendulum", Mechanism::kHingeChain, 2, 5.0, MujocoScene::kHingeChain},
      {"hinge_chain10", Mechanism::kHingeChain, 10, 5.0, MujocoScene::kHingeChain},
      {"hinge_chain200", Mechanism::kHingeChain, 200, 1.0, MujocoScene::kHingeChain},
      {"humanoid", Mechanism::kHumanoid, 0, 5.0, MujocoScene::kHumanoid},
      {"rssr", Mechanism::kRssr, 0, 3.0, MujocoScene::kRssr},
      {"four_bar10", Mechanism::kFourBar, 10, 5.0, MujocoScene::kFourBar}};
  return scenes;
}

using Centres = std::vector<Vec3<double>>;

// the N-four-bar's centres at t = duration on its exact motion (above)
Centres FourBarReduction(int n, double duration) {
  const double theta = ReducedCrankAngles(NFourBarInertia(n), NFourBarLoad(n, 9.81), duration, duration).back();
  Centres centres;
  for (int i = 0; i <= n; ++i) centres.emplace_back(i + 0.5 * std::cos(theta), 0.5 * std::sin(theta), 0.0);
  for (int i = 0; i < n; ++i) centres.emplace_back(i + 0.5 + std::cos(theta), std::sin(theta), 0.0);
  return centres;
}

constexpr SimbodySettings kReferenceSettings{SimbodyIntegrator::kRungeKuttaMerson, 1e-12};

const Centres& Reference(const PeerScene& scene) {
  static std::map<std::string, Centres> references;
  auto [it, fresh] = references.try_emplace(scene.name);
  if (fresh) {
    if (scene.mechanism == Mechanism::kFourBar) {
      it->second = FourBarReduction(scene.n, scene.duration);
    } else {
      const SimbodyScene simbody(scene.mechanism, scene.n);
      it->second = simbody.Run(kReferenceSettings, scene.duration);
    }
  }
  return it->second;
}

// What the untimed run observed.
struct Observed {
  double worst_violation = 0.0;
  Centres end;
  int steps = 0;

  void Report(benchmark::State& state, const PeerScene& scene) const {
    const Centres& reference = Reference(scene);
    if (end.size() != reference.size()) {
      state.SkipWithError("the engine's scene has another number of bodies than the reference's");
      return;
    }
    double error = 0.0;
    for (size_t k = 0; k < end.size(); ++k) error = std::max(error, (end[k] - reference[k]).norm());
    state.counters["error_m"] = error;
    state.counters["max_violation_m"] = worst_violation;
    state.counters["duration_s"] = scene.duration;
    state.counters["steps"] = steps;
  }
};

// tether: rk4 at h = `step` with Baumgarte (tolerance 0), or rk45 with projection at `tolerance`
void Tether(benchmark::State& state, PeerScene scene, double tolerance, double step) {
  Model<double> model = TetherPeerScene(scene.mechanism, scene.n, true, scene.duration);
  model.simulation.step = step;
  if (tolerance > 0.0) {
    model.simulation.integrator = Integrator::kRk45;
    model.simulation.step = scene.duration;  // one output, at the end: the tolerance alone sets the steps
    model.simulation.tolerance = tolerance;
    model.stabilization.method = Stabilization::kProjection;
  }
  Observed seen;
  try {
    const RunReport report = Simulate<double>(model, RunOptions{}, [&](const Sample<double>& s) {
      seen.worst_violation = std::max(seen.worst_violation, s.constraint_error);
      seen.end.clear();
      for (const Body<double>& body : model.bodies) {
        seen.end.push_back(Translation(model.dimension, s.q.data() + body.q_offset));
      }
    });
    if (tolerance == 0.0) seen.steps = static_cast<int>(report.steps);  // (rk45's internal steps are not counted)
  } catch (const SimulationDiverged& e) {
    state.SkipWithError(e.what());
    return;
  }
  RunOptions quiet;
  quiet.every = static_cast<int>(StepCount(model.simulation));
  quiet.energy = false;
  for (auto _ : state) {
    Simulate<double>(model, quiet, [](const Sample<double>& s) { benchmark::DoNotOptimize(s.q.data()); });
  }
  seen.Report(state, scene);
}

void Mujoco(benchmark::State& state, PeerScene scene, double step) {
  MujocoSettings settings;
  settings.step = step;
  const MjModelPtr model = LoadMujoco(MujocoModel(scene.mujoco, scene.n, true, settings));
  const MujocoProbe probe(*model, scene.mujoco);
  const int steps = static_cast<int>(std::lround(scene.duration / model->opt.timestep));
  Observed seen;
  {
    const MjDataPtr data = InitialMujocoState(*model, scene.mujoco);
    seen.worst_violation = probe.Violation(*data);
    for (int k = 0; k < steps; ++k) {
      mj_step(model.get(), data.get());
      mj_forward(model.get(), data.get());  // positions of the state after the step
      seen.worst_violation = std::max(seen.worst_violation, probe.Violation(*data));
    }
    const std::string warnings = MujocoWarnings(*data);
    if (!warnings.empty()) {
      state.SkipWithError(warnings.c_str());
      return;
    }
    seen.end = probe.Centres(*data);
    seen.steps = steps;
  }
  for (auto _ : state) {
    state.PauseTiming();
    const MjDataPtr data = InitialMujocoState(*model, scene.mujoco);
    state.ResumeTiming();
    for (int k = 0; k < steps; ++k) mj_step(model.get(), data.get());
    benchmark::DoNotOptimize(data->qpos);
  }
  seen.Report(state, scene);
}

void Simbody(benchmark::State& state, PeerScene scene, SimbodySettings settings) {
  const SimbodyScene simbody(scene.mechanism, scene.n);
  Observed seen;
  try {
    seen.end = simbody.Run(
        settings, scene.duration,
        [&](const SimTK::State& s) { seen.worst_violation = std::max(seen.worst_violation, simbody.Violation(s)); },
        &seen.steps);
  } catch (const std::exception& e) {
    state.SkipWithError(e.what());
    return;
  }
  for (auto _ : state) benchmark::DoNotOptimize(simbody.Run(settings, scene.duration).data());
  seen.Report(state, scene);
}

std::string Accuracy(double accuracy) {
  char text[16];
  std::snprintf(text, sizeof text, "%.0e", accuracy);
  return text;
}

std::string StepName(double step) {  // 0.002, 0.0005, 0.00025
  char text[16];
  std::snprintf(text, sizeof text, "%g", step);
  return text;
}

// the sweep of tether's rk45 and Simbody's Runge-Kutta-Merson; CPodes runs at 1e-6 and 1e-8
constexpr double kAccuracies[] = {1e-4, 1e-6, 1e-8, 1e-10, 1e-12};
// the steps of tether's rk4 and MuJoCo's RK4 besides h = 1e-3 (s)
constexpr double kSteps[] = {2e-3, 5e-4, 2.5e-4};

// Names are SCENE/ENGINE/METHOD: hinge_chain200/tether/rk4, rssr/simbody/rkm_1e-06, four_bar10/mujoco/rk4, ...
void Register() {
  for (const PeerScene& scene : Scenes()) {
    RegisterPeerRun(scene.name + "/tether/rk4", Tether, scene, 0.0, kPeerStep);
    for (double tolerance : kAccuracies)
      RegisterPeerRun(scene.name + "/tether/rk45_" + Accuracy(tolerance), Tether, scene, tolerance, kPeerStep);
    RegisterPeerRun(scene.name + "/mujoco/rk4", Mujoco, scene, kPeerStep);
    for (double step : kSteps) {  // the fixed-step integrators' sweep, for the work-precision diagrams
      RegisterPeerRun(scene.name + "/tether/rk4_h" + StepName(step), Tether, scene, 0.0, step);
      RegisterPeerRun(scene.name + "/mujoco/rk4_h" + StepName(step), Mujoco, scene, step);
    }
    for (double accuracy : kAccuracies) {
      RegisterPeerRun(scene.name + "/simbody/rkm_" + Accuracy(accuracy), Simbody, scene,
                      SimbodySettings{SimbodyIntegrator::kRungeKuttaMerson, accuracy});
    }
    for (double accuracy : {1e-6, 1e-8}) {
      RegisterPeerRun(scene.name + "/simbody/cpodes_" + Accuracy(accuracy), Simbody, scene,
                      SimbodySettings{SimbodyIntegrator::kCPodes, accuracy});
    }
  }
}

}  // namespace
}  // namespace tether::bench

int main(int argc, char** argv) { return tether::bench::RunPeerBenchmarks(argc, argv, tether::bench::Register); }
