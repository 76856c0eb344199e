#include "tether_models.h"

#include <string>

#include "bench_models.h"
#include "tether/dynamics/kinematics.h"

namespace tether::bench {

Model<double> TetherPeerScene(Mechanism mechanism, int n, bool rk4, double duration) {
  Model<double> model;
  if (mechanism == Mechanism::kChain) {
    model.dimension = 3;
    for (int k = 0; k < n; ++k) {
      AddBody<double>(&model, "p" + std::to_string(k), BodyKind::kParticle, 1.0, 0.0, Vec3<double>(k + 1.0, 0, 0), 0.0,
                      Vec3<double>::Zero(), 0.0);
      model.distances.push_back({k, BodyPoint<double>{k - 1}, BodyPoint<double>{k}, 1.0});
    }
    model.gravity.push_back({0, Vec3<double>(0, 0, -9.81)});
  } else {
    model = FourBar(1, KktSolver::kAuto);
  }
  model.simulation.integrator = rk4 ? Integrator::kRk4 : Integrator::kSymplecticEuler;
  model.simulation.step = 1e-3;
  model.simulation.duration = duration;
  model.stabilization.method = Stabilization::kBaumgarte;
  model.stabilization.alpha = 100.0;
  model.stabilization.beta = 2500.0;
  model.stabilization.gains_from_rule = false;
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
