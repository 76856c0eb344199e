#include "tether_models.h"

#include "bench_models.h"
#include "tether/dynamics/kinematics.h"

namespace tether::bench {

Model<double> TetherPeerScene(Mechanism mechanism, int n, bool rk4, double duration) {
  const Integrator integrator = rk4 ? Integrator::kRk4 : Integrator::kSymplecticEuler;
  Model<double> model = mechanism == Mechanism::kChain ? HorizontalChain(n, integrator, KktSolver::kAuto, 3)
                                                       : FourBar(1, KktSolver::kAuto);
  model.simulation.integrator = integrator;
  model.simulation.step = kPeerStep;
  model.simulation.duration = duration;
  SetGains(&model, 100.0, 2500.0);
  return model;
}

double GravityPotential(const Model<double>& model, const VecX<double>& q) {
  double potential = 0.0;
  for (const GravityEffect<double>& g : model.gravity) {
    for (const Body<double>& body : model.bodies) {
      potential -= body.mass * g.acceleration.dot(Translation(body, model.dimension, q));
    }
  }
  return potential;
}

}  // namespace tether::bench
