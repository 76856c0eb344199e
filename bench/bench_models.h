// Models built in code for the benchmarks.
#pragma once

#include "tether/dynamics/model.h"

namespace tether::bench {

// A planar chain of n unit-mass particles on 1/n m links, hanging from the origin and released horizontal,
// under gravity, with the given integrator and KKT solver path.
Model<double> HorizontalChain(int n, Integrator integrator, KktSolver solver);

// The IFToMM A02 N-four-bar: n parallelograms of uniform 1 m, 1 kg bars (2n + 1 rigid bodies, 4n + 2 pin
// constraints, 8n + 4 rows), cranks vertical and turning at -1 rad/s, under gravity.
Model<double> FourBar(int n, KktSolver solver);

// scenes/pendulum.json's pendulum (1 kg, 1 m, released from 60 degrees) with the given integrator and step.
Model<double> Pendulum(Integrator integrator, double step);

}  // namespace tether::bench
