// Models built in code for the benchmarks, and the loop that steps them.
#pragma once

#include <benchmark/benchmark.h>

#include <nlohmann/json.hpp>

#include "tether/dynamics/model/model.h"

namespace tether::bench {

// A chain of n unit-mass particles on 1 m links, hanging from the origin and released horizontal along +x, under
// gravity along -y (planar) or -z (dimension 3), with the given integrator and KKT solver path and Baumgarte
// alpha = 20, beta = 100. (Short links under the weight of a long chain make transverse modes too fast for
// h = 1e-3: 1000 links of 1 mm reach about 3000 rad/s.)
Model<double> HorizontalChain(int n, Integrator integrator, KktSolver solver, int dimension = 2);

// Baumgarte stabilization with these gains (instead of the rule's).
void SetGains(Model<double>* model, double alpha, double beta);

// The same chain as a scene document (rk4, step 1e-3 s, the given duration, solver "auto", Baumgarte alpha = 20,
// beta = 100), with every mass and link length written out so that JSON Pointers can name them as parameters
// (/bodies/k/mass, /constraints/k/length). Parse it with tether::ParseScene.
nlohmann::json HorizontalChainScene(int n, double duration);

// A planar binary tree of n unit-mass particles on 1 m links: particle 0 hangs from the origin, particle k from
// particle (k - 1) / 2, left children 0.4 rad and right children 0.8 rad off the downward vertical, at rest
// under gravity; rk4, Baumgarte alpha = 20, beta = 100, the given KKT solver path. Its Schur complement has a
// dense block where a parent meets its children (the line graph of the tree), so an elimination order from the
// leaves up factors it without fill.
Model<double> BinaryTree(int n, KktSolver solver);

// The IFToMM A02 N-four-bar: n parallelograms of uniform 1 m, 1 kg bars (2n + 1 rigid bodies, 3n + 1 pin
// constraints, 6n + 2 rows), cranks vertical and turning at -1 rad/s, under gravity.
Model<double> FourBar(int n, KktSolver solver);

// A chain of n rigid rods (1 kg, 1 m, radius 2 cm) on hinges about y, hanging from the origin and released
// horizontal along +x under gravity along -z; Baumgarte alpha = 20, beta = 100.
Model<double> HingeChain(int n, Integrator integrator, KktSolver solver);

// A binary tree of n such rods on hinges about y: rod 0 hangs from the origin, rod k from the lower end of rod
// (k - 1) / 2, left children 0.4 rad and right children 0.8 rad off the downward vertical (in the x-z plane), at
// rest under gravity; rk4, Baumgarte alpha = 20, beta = 100.
Model<double> HingeTree(int n, KktSolver solver);

// Principal moments of a solid rod of radius 2 cm along body x.
Vec3<double> RodInertia(double mass, double length);

// scenes/pendulum.json's pendulum (1 kg, 1 m, released from 60 degrees) with the given integrator and step.
Model<double> Pendulum(Integrator integrator, double step);

// Steps the model inside the benchmark loop; one item is one step. The state goes back to the initial one every
// kStepsPerRun steps (with the clock paused), so every measured step is a healthy one: a chain dropped from
// horizontal whips and diverges after about 2 s, and a diverged step is cheap and meaningless.
void StepModel(benchmark::State& state, const Model<double>& model);

}  // namespace tether::bench
