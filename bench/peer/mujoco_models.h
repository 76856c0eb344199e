// The peer benchmark's scenes in MuJoCo (2.2, C API), built as MJCF text and loaded from memory.
//
// Chain: n point masses (1 kg, three slide joints each, no geometry, so no contacts) on 1 m links, the first
// hung from the origin, released at rest along +x under gravity -9.81 z. Each link is a spatial tendon between
// two sites held at its initial length by a tendon equality: MuJoCo's way of writing a distance constraint
// between particles. Four-bar: scenes/four_bar.json's parallelogram (1 m, 1 kg bars, inertia 1/12 about the
// centre) in the x-z plane: crank0 and crank1 hinged to the ground 1 m apart, the coupler hinged to crank0's tip,
// and a connect equality closing the loop at crank1's tip; cranks vertical and turning at 1 rad/s.
//
// Settings, written out in the MJCF although they are MuJoCo's defaults: the Newton solver, 100 iterations,
// tolerance 1e-8, solref (0.02, 1) and solimp (0.9, 0.95, 0.001) on every equality; h = 1e-3; integrator
// "Euler" (semi-implicit: velocity first) or "RK4".
#pragma once

#include <mujoco/mujoco.h>

#include <memory>
#include <string>

namespace tether::bench {

struct MjModelDeleter {
  void operator()(mjModel* m) const { mj_deleteModel(m); }
};
struct MjDataDeleter {
  void operator()(mjData* d) const { mj_deleteData(d); }
};
using MjModelPtr = std::unique_ptr<mjModel, MjModelDeleter>;
using MjDataPtr = std::unique_ptr<mjData, MjDataDeleter>;

enum class PeerScene { kChain, kFourBar };

// The MJCF text of a scene (n: the chain's particles; ignored for the four-bar).
std::string MujocoScene(PeerScene scene, int n, bool rk4);

// Compiles MJCF text; throws std::runtime_error with MuJoCo's message when it fails.
MjModelPtr LoadMujoco(const std::string& xml);

// A fresh state at the scene's initial conditions (the four-bar's cranks turning).
MjDataPtr InitialMujocoState(const mjModel& model, PeerScene scene);

// The largest constraint violation of the current state, in metres: | |p_i - p_{i-1}| - 1 | over the chain's
// links, or the gap between the coupler's end and crank1's tip. Needs the positions of a forward pass.
double MujocoViolation(const mjModel& model, const mjData& data, PeerScene scene);

}  // namespace tether::bench
