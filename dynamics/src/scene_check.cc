#include "tether/dynamics/scene_check.h"

#include <Eigen/QR>
#include <Eigen/SVD>
#include <set>

#include "tether/dynamics/constraint_rows.h"
#include "tether/dynamics/schur_solver.h"

namespace tether {

SceneCheck CheckScene(const Model<double>& model) {
  SceneCheck check;
  const std::vector<RowInfo> infos = DescribeRows(model);
  std::vector<ConstraintRow<double>> rows(infos.size());
  check.coordinates = model.NumCoordinates();
  check.constraint_rows = static_cast<int>(rows.size());
  check.solver = ResolveSolver(model.simulation.solver) == KktSolver::kDense ? "dense" : "sparse";
  check.degrees_of_freedom = check.coordinates;
  if (rows.empty()) return check;
  EvaluateConstraintRows(model, model.q0, model.v0, false, &rows);
  const Violation violation = LargestViolation(infos, rows);
  check.initial_violation = violation.largest;
  check.worst_constraint = violation.scene_index;

  // J M^-1/2, row by row from the body blocks
  Eigen::MatrixXd scaled = Eigen::MatrixXd::Zero(check.constraint_rows, check.coordinates);
  for (int i = 0; i < check.constraint_rows; ++i) {
    for (const BodyVector<double>* g : {&rows[i].a, &rows[i].b}) {
      if (g->body == kWorld) continue;
      const Body<double>& body = model.bodies[g->body];
      for (int k = 0; k < model.dimension; ++k) scaled(i, body.offset + k) += g->translation[k] / std::sqrt(body.mass);
      if (body.kind == BodyKind::kRigid) scaled(i, body.offset + 2) += g->rotation / std::sqrt(body.inertia);
    }
  }
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(scaled);
  const Eigen::VectorXd sigma = svd.singularValues();
  const double largest = sigma.size() ? sigma[0] : 0.0;
  while (check.rank < sigma.size() && sigma[check.rank] > kRankTolerance * largest) ++check.rank;
  check.degrees_of_freedom = check.coordinates - check.rank;
  check.condition_number = check.rank ? largest / sigma[check.rank - 1] : 1.0;

  // the rows the rank-revealing QR of the transpose leaves out after the first `rank` pivots
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(scaled.transpose());
  std::set<int> redundant;
  for (int k = check.rank; k < check.constraint_rows; ++k) {
    redundant.insert(infos[qr.colsPermutation().indices()[k]].scene_index);
  }
  check.redundant_constraints.assign(redundant.begin(), redundant.end());
  return check;
}

}  // namespace tether
