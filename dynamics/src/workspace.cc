#include "tether/dynamics/workspace.h"

#include "tether/dynamics/constrained_dynamics.h"

namespace tether {

template <typename T>
Workspace<T>::Workspace(const Model<T>& model, bool factor_jet_matrices)
    : infos(DescribeRows(model)),
      pattern(infos, static_cast<int>(model.bodies.size())),
      solver(pattern, model.simulation.solver, factor_jet_matrices),
      inverse_mass(InverseMassDiagonal(model)),
      rows(infos.size()),
      schur(pattern.nonzeros(), T(0.0)) {
  const int n = model.NumCoordinates();
  const int m = static_cast<int>(infos.size());
  force.setZero(n);
  reaction.setZero(n);
  rhs.setZero(m);
  lambda.setZero(m);
  for (int s = 0; s < 7; ++s) {
    stage_q[s].setZero(n);
    stage_v[s].setZero(n);
  }
  trial_q.setZero(n);
  trial_v.setZero(n);
  next_q.setZero(n);
  next_v.setZero(n);
  error_q.setZero(n);
  error_v.setZero(n);
}

template struct Workspace<double>;
template struct Workspace<Jet>;

}  // namespace tether
