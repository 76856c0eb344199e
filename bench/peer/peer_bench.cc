// tether against MuJoCo on the same scenes, side by side in one run (bench/peer/README.md): the chains of
// tether_models.h and mujoco_models.h (n = 10, 50, 200, 1000; MuJoCo's two ways of writing a chain), the four-bar,
// the 3D hinge chains of rigid rods (n = 10 to 1000), the humanoid-sized tree and MuJoCo's humanoid.xml hanging by
// its torso, each with symplectic Euler
// against MuJoCo's semi-implicit Euler and rk4 against RK4, h = 1e-3.
//
// Every benchmark first runs its scene once untimed, observing every step: the largest constraint violation,
// and the largest energy error |E(t) - E(0)| in J and as a fraction of the largest drop of potential energy
// (what soft constraints eat of it). Then the same run, unobserved, is timed; items are steps, so items_per_second
// is steps per second. tether's timed run includes its set-up (workspace, symbolic analysis, assembly of the
// initial state); MuJoCo's excludes mj_makeData and the initial mj_forward.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "mujoco_models.h"
#include "tether/dynamics/integration/simulator.h"
#include "tether/dynamics/model/errors.h"
#include "tether_models.h"

namespace tether::bench {
namespace {

static_assert(MujocoSettings{}.step == kPeerStep, "both engines step alike");

struct PeerCase {
  Mechanism mechanism;
  int n;  // the chain's particles or rods, the four-bar's parallelograms
  bool rk4;
  double duration;           // s
  bool conservative = true;  // false where the scene damps (its energy error then measures no integrator)

  int Steps() const { return static_cast<int>(std::lround(duration / kPeerStep)); }
};

// What the untimed run observed.
class Observed {
 public:
  void Track(double violation, double energy, double potential) {
    if (first_) {
      energy0_ = energy;
      potential0_ = potential;
      first_ = false;
    }
    worst_violation_ = std::max(worst_violation_, violation);
    worst_energy_error_ = std::max(worst_energy_error_, std::abs(energy - energy0_));
    largest_potential_drop_ = std::max(largest_potential_drop_, potential0_ - potential);
  }

  void Report(benchmark::State& state, const PeerCase& c) const {
    state.SetItemsProcessed(static_cast<int64_t>(state.iterations()) * c.Steps());
    state.counters["max_violation_m"] = worst_violation_;
    state.counters["energy_error_J"] = worst_energy_error_;
    state.counters["energy_error_of_drop"] = worst_energy_error_ / std::max(largest_potential_drop_, 1e-300);
    state.counters["conservative"] = c.conservative ? 1 : 0;
    state.counters["steps"] = c.Steps();
  }

 private:
  bool first_ = true;
  double energy0_ = 0.0, potential0_ = 0.0;
  double worst_violation_ = 0.0, worst_energy_error_ = 0.0, largest_potential_drop_ = 0.0;
};

void Tether(benchmark::State& state, PeerCase c, Stabilization stabilization) {
  Model<double> model = TetherPeerScene(c.mechanism, c.n, c.rk4, c.duration);
  model.stabilization.method = stabilization;
  Observed seen;
  try {
    Simulate<double>(model, RunOptions{}, [&](const Sample<double>& s) {
      seen.Track(s.constraint_error, s.energy, GravityPotential(model, s.q));
    });
  } catch (const SimulationDiverged& e) {
    state.SkipWithError(e.what());
    return;
  }
  RunOptions quiet;
  quiet.every = c.Steps();
  for (auto _ : state)
    Simulate<double>(model, quiet, [](const Sample<double>& s) { benchmark::DoNotOptimize(s.q.data()); });
  seen.Report(state, c);
}

void Mujoco(benchmark::State& state, PeerCase c, MujocoScene scene) {
  const MjModelPtr model = LoadMujoco(MujocoModel(scene, c.n, c.rk4));
  const MujocoProbe probe(*model, scene);
  Observed seen;
  {
    const MjDataPtr data = InitialMujocoState(*model, scene);
    seen.Track(probe.Violation(*data), data->energy[0] + data->energy[1], data->energy[0]);
    for (int k = 0; k < c.Steps(); ++k) {
      mj_step(model.get(), data.get());
      mj_forward(model.get(), data.get());  // positions and energy of the state after the step
      seen.Track(probe.Violation(*data), data->energy[0] + data->energy[1], data->energy[0]);
    }
    const std::string warnings = MujocoWarnings(*data);
    if (!warnings.empty()) {
      state.SkipWithError(warnings.c_str());
      return;
    }
  }
  for (auto _ : state) {
    state.PauseTiming();
    const MjDataPtr data = InitialMujocoState(*model, scene);
    state.ResumeTiming();
    for (int k = 0; k < c.Steps(); ++k) mj_step(model.get(), data.get());
    benchmark::DoNotOptimize(data->qpos);
  }
  seen.Report(state, c);
}

// Names are SCENE/INTEGRATOR/ENGINE: chain200/rk4/tether, chain200/rk4/mujoco_slides, four_bar/euler/mujoco, ...
// The four-bar also runs tether with its projection stabilization (positions and velocities put back onto the
// constraints after every step), to show what exact constraints cost there.
void Register() {
  for (bool rk4 : {false, true}) {
    const std::string integrator = rk4 ? "/rk4" : "/euler";
    for (int n : {10, 50, 200, 1000}) {
      const PeerCase c{Mechanism::kChain, n, rk4, n == 1000 ? 1.0 : 10.0};
      const std::string scene = "chain" + std::to_string(n) + integrator;
      RegisterPeerRun(scene + "/tether", Tether, c, Stabilization::kBaumgarte);
      RegisterPeerRun(scene + "/mujoco_slides", Mujoco, c, MujocoScene::kChainOfSlides);
      RegisterPeerRun(scene + "/mujoco_free", Mujoco, c, MujocoScene::kChainOfFreeBodies);
    }
    const PeerCase c{Mechanism::kFourBar, 1, rk4, 10.0};
    RegisterPeerRun("four_bar" + integrator + "/tether", Tether, c, Stabilization::kBaumgarte);
    RegisterPeerRun("four_bar" + integrator + "/tether_projection", Tether, c, Stabilization::kProjection);
    RegisterPeerRun("four_bar" + integrator + "/mujoco", Mujoco, c, MujocoScene::kFourBar);
    // rigid bodies on hinges: MuJoCo in reduced coordinates (its factorization of a chain grows with n^2 and more)
    for (int n : {10, 50, 200, 1000}) {
      const PeerCase h{Mechanism::kHingeChain, n, rk4, n >= 1000 ? 0.05 : n >= 200 ? 1.0 : 5.0};
      const std::string scene = "hinge_chain" + std::to_string(n) + integrator;
      RegisterPeerRun(scene + "/tether", Tether, h, Stabilization::kBaumgarte);
      RegisterPeerRun(scene + "/mujoco", Mujoco, h, MujocoScene::kHingeChain);
    }
    const PeerCase humanoid{Mechanism::kHumanoid, 0, rk4, 5.0};
    RegisterPeerRun("humanoid" + integrator + "/tether", Tether, humanoid, Stabilization::kBaumgarte);
    RegisterPeerRun("humanoid" + integrator + "/mujoco", Mujoco, humanoid, MujocoScene::kHumanoid);
    const PeerCase file{Mechanism::kHumanoidFile, 0, rk4, 5.0, false};  // its joints are damped
    RegisterPeerRun("humanoid_file" + integrator + "/tether", Tether, file, Stabilization::kBaumgarte);
    RegisterPeerRun("humanoid_file" + integrator + "/mujoco", Mujoco, file, MujocoScene::kHumanoidFile);
  }
}

}  // namespace
}  // namespace tether::bench

int main(int argc, char** argv) { return tether::bench::RunPeerBenchmarks(argc, argv, tether::bench::Register); }
