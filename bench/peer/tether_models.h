// The peer benchmark's scenes in tether, the same mechanisms as mujoco_models.h builds in MuJoCo.
//
// Chain: n particles of 1 kg on 1 m distance constraints, the first hung from the origin, released at rest along
// +x under gravity -9.81 z (3D). Four-bar: bench_models.h's FourBar(n), n parallelograms (n = 1:
// scenes/four_bar.json; n > 1: the IFToMM A02 N-four-bar) in the x-y plane, gravity -y. Both with Baumgarte gains
// alpha = 100, beta = 2500: the error dynamics C'' + 100 C' + 2500 C = 0 are MuJoCo's default solref (0.02, 1)
// (time constant 0.02 s, damping ratio 1) written as gains, so both engines pull drift back equally hard; tether
// holds the constraints exactly at the acceleration level, MuJoCo softly.
// Hinge chain: bench_models.h's HingeChain (rigid rods on hinges about y); humanoid: humanoid_tree.h's tree, the
// torso welded to the world. MuJoCo builds both in reduced coordinates, so only tether has constraints there.
// Humanoid file: MuJoCo's own humanoid.xml hanging by its torso, imported as `tether import --fix torso
// --no-contact` imports it (the torso and head the world's, 14 moving bodies, the hands welded to the forearms),
// its joint ranges removed; MuJoCo runs the same file with the torso's free joint removed and its contacts and
// limits disabled (mujoco_models.h).
// RSSR: scenes/rssr.json as shipped (rssr_linkage.h describes it for the peers), its gains and integrator replaced.
// h = 1e-3; symplectic_euler is paired with MuJoCo's semi-implicit "Euler", rk4 with "RK4"; KKT solver auto.
#pragma once

#include "tether/dynamics/model/model.h"

namespace tether::bench {

enum class Mechanism { kChain, kFourBar, kHingeChain, kHumanoid, kHumanoidFile, kRssr };

inline constexpr double kPeerStep = 1e-3;  // s, both engines

// MuJoCo's own humanoid (Debian's libmujoco-samples).
inline constexpr const char* kMujocoHumanoidFile = "/usr/share/mujoco/model/humanoid/humanoid.xml";

// n: the chain's particles or rods, the four-bar's parallelograms (ignored for the humanoids and the RSSR).
Model<double> TetherPeerScene(Mechanism mechanism, int n, bool rk4, double duration);

// Gravity's potential energy sum m g height, J (height: the last coordinate of a position).
double GravityPotential(const Model<double>& model, const VecX<double>& q);

}  // namespace tether::bench
