// The peer benchmark's scenes in MuJoCo (2.2, C API), built as MJCF text and loaded from memory.
//
// Chains: n point masses of 1 kg on 1 m links, the first hung from the origin, released at rest along +x under
// gravity -9.81 z; no geometry, so no contacts. MuJoCo has no distance constraint between particles; the two
// usual ways of writing one are both here:
//   kChainOfSlides      every mass on three slide joints, every link a spatial tendon between two sites held at
//                       its initial length by a tendon equality (nv = 3n, n equality rows);
//   kChainOfFreeBodies  every link a free body with its mass at its tip (inertia 1e-6 about the tip) and its
//                       base held at the previous tip by a connect equality, a ball joint (nv = 6n, 3n rows).
// Four-bar: n parallelograms of 1 m, 1 kg bars (inertia 1/12 about the centre) in the x-z plane (n = 1:
// scenes/four_bar.json; n > 1: the IFToMM A02 N-four-bar): crank i hinged to the ground at (i, 0, 0), coupler i
// hinged to crank i's tip, and a connect equality closing each loop at crank i + 1's tip; cranks vertical and
// turning at 1 rad/s about y (their tips moving along +x, as tether's do in its x-y plane).
// RSSR: rssr_linkage.h's spatial four-bar: the crank and the rocker on hinges, the coupler on a ball joint at the
// crank's tip, a connect equality at the rocker's tip; the motor's torque as an applied generalized force.
//
// Hinge chain: bench_models.h's HingeChain as nested bodies on hinge joints (reduced coordinates); MuJoCo 2.2's
// XML parser refuses elements nested deeper than about 100 levels, so the chain is split into files of 40 links,
// each included inside the innermost body of the one before. Humanoid: humanoid_tree.h's tree (hips and shoulders
// three hinges at one point, ankles two). Neither has equality constraints.
//
// Settings, written out in the MJCF although they are MuJoCo's defaults: the Newton solver, 100 iterations,
// tolerance 1e-8, solref (0.02, 1) and solimp (0.9, 0.95, 0.001) on every equality; h = 1e-3; integrator
// "Euler" (semi-implicit: velocity first) or "RK4". MujocoSettings can harden the constraints (a test compares
// the mechanisms with MuJoCo's constraints nearly rigid).
#pragma once

#include <benchmark/benchmark.h>
#include <mujoco/mujoco.h>

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "tether/dynamics/scalars/scalar.h"
#include "tether_models.h"

namespace tether::bench {

struct MjModelDeleter {
  void operator()(mjModel* m) const { mj_deleteModel(m); }
};
struct MjDataDeleter {
  void operator()(mjData* d) const { mj_deleteData(d); }
};
using MjModelPtr = std::unique_ptr<mjModel, MjModelDeleter>;
using MjDataPtr = std::unique_ptr<mjData, MjDataDeleter>;

enum class MujocoScene { kChainOfSlides, kChainOfFreeBodies, kFourBar, kHingeChain, kHumanoid, kHumanoidFile, kRssr };
// kHumanoidFile: kMujocoHumanoidFile (tether_models.h) with the torso's free joint removed (it hangs by its
// torso), contacts and joint limits disabled, and the step and integrator asked.

struct MujocoSettings {
  double step = 1e-3;           // s
  double time_constant = 0.02;  // solref (time constant, damping ratio 1)
  double impedance = 0.9;       // solimp (impedance, impedance + 0.05 at most 1, width 0.001)
};

// The MJCF files of a scene, (name, text), the main file first (n: the chain's masses or rods, the four-bar's
// parallelograms; ignored for the humanoid and the RSSR).
using MujocoFiles = std::vector<std::pair<std::string, std::string>>;
MujocoFiles MujocoModel(MujocoScene scene, int n, bool rk4, const MujocoSettings& settings = {});

// The main file's text of a single-file scene.
std::string MujocoXml(MujocoScene scene, int n, bool rk4, const MujocoSettings& settings = {});

// Compiles MJCF; throws std::runtime_error with MuJoCo's message when it fails.
MjModelPtr LoadMujoco(const MujocoFiles& files);
MjModelPtr LoadMujoco(const std::string& xml);

// A fresh state at the scene's initial conditions (the four-bar's cranks turning, the RSSR's motor on), positions
// computed.
MjDataPtr InitialMujocoState(const mjModel& model, MujocoScene scene);

// The warnings MuJoCo raised on this data ("too many constraints", "bad number in qacc", ...), as one line;
// empty when there were none. A run with a warning measured a broken model.
std::string MujocoWarnings(const mjData& data);

// The main() of a benchmark that fails a MuJoCo run with a warning: MuJoCo's warnings are kept in
// mjData::warning (MujocoWarnings) instead of printed, `register_benchmarks` registers the runs, and Google
// Benchmark runs those the command line selects.
int RunPeerBenchmarks(int argc, char** argv, void (*register_benchmarks)());

// Registers one peer run as the side-by-side benchmarks time them: the whole run is one iteration (timed in
// milliseconds of wall time), repeated three times.
template <typename Function, typename... Arguments>
void RegisterPeerRun(const std::string& name, Function&& function, Arguments... arguments) {
  benchmark::RegisterBenchmark(name.c_str(), function, arguments...)
      ->Unit(benchmark::kMillisecond)
      ->UseRealTime()
      ->Iterations(1)
      ->Repetitions(3);
}

// What the benchmark reads off a state: the sites it needs, looked up once.
class MujocoProbe {
 public:
  MujocoProbe(const mjModel& model, MujocoScene scene);

  // The largest violation of the scene's equality constraints, in metres: the tendons' length errors
  // | |p_i - p_{i-1}| - 1 |, or the gaps of the connect equalities (none on the hinge chain and the humanoid). Needs
  // the positions of a forward pass.
  double Violation(const mjData& data) const;

  // The bodies' centres of mass in tether's order and frame (tether_models.h; the four-bar's x-z plane is tether's
  // x-y): the hinge chain's links, the humanoid's bodies but the torso, the four-bar's cranks then its couplers,
  // the RSSR's crank, coupler and rocker. Empty for the chains of particles.
  std::vector<Vec3<double>> Centres(const mjData& data) const;

  // Where chain mass i is (a forward pass's positions).
  Vec3<double> Mass(const mjData& data, int i) const { return Site(data, masses_[i]); }

 private:
  static Vec3<double> Site(const mjData& data, int site) {
    return Vec3<double>(data.site_xpos[3 * site], data.site_xpos[3 * site + 1], data.site_xpos[3 * site + 2]);
  }

  MujocoScene scene_;
  std::vector<int> masses_, bases_;        // chains: the site of every mass, and of every link's base (free bodies)
  std::vector<std::pair<int, int>> gaps_;  // the two sites of every connect equality
  std::vector<int> bodies_;                // Centres' bodies
};

}  // namespace tether::bench
