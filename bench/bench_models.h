// Models built in code for the benchmarks.
#pragma once

#include "tether/dynamics/model.h"

namespace tether::bench {

// A planar chain of n unit-mass particles on 1/n m links, hanging from the origin and released horizontal,
// under gravity, with the given integrator and KKT solver path.
Model<double> HorizontalChain(int n, Integrator integrator, KktSolver solver);

// scenes/pendulum.json's pendulum (1 kg, 1 m, released from 60 degrees) with the given integrator and step.
Model<double> Pendulum(Integrator integrator, double step);

}  // namespace tether::bench
