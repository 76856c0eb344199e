#include "tether/dynamics/scene_check.h"

#include <Eigen/Eigenvalues>
#include <Eigen/QR>
#include <Eigen/SVD>
#include <set>

#include "tether/dynamics/constraint_rows.h"
#include "tether/dynamics/effects.h"
#include "tether/dynamics/errors.h"
#include "tether/dynamics/schur_solver.h"
#include "tether/dynamics/simulator.h"

namespace tether {

SceneCheck CheckScene(const Model<double>& model) {
  SceneCheck check;
  const State<double> start = InitialState(model);
  const ConstraintSet<double> set = BuildConstraintSet(model, start.q);
  const std::vector<RowInfo> infos = DescribeRows(model, set);
  std::vector<ConstraintRow<double>> rows(infos.size());
  check.coordinates = model.NumVelocities();
  check.constraint_rows = static_cast<int>(rows.size());
  check.solver = ResolveSolver(model.simulation.solver) == KktSolver::kDense ? "dense" : "sparse";
  check.degrees_of_freedom = check.coordinates;
  try {
    RunReport report;
    AssembledInitialState(model, &report);
  } catch (const InputError& e) {
    check.assembly_error = e.what();
  }
  if (rows.empty()) return check;
  BodyFrames<double> frames;
  UpdateFrames(model, start.q, start.v, false, &frames);
  EvaluateConstraintRows(model, set, frames, start.q, start.v, false, &rows);
  const Violation violation = LargestViolation(infos, rows);
  check.initial_violation = violation.largest;
  check.worst_constraint = violation.scene_index;

  // J M^-1/2, row by row from the body blocks
  std::vector<Mat3<double>> rotational(model.bodies.size());  // I_P^-1/2 of 3D bodies
  for (size_t b = 0; b < model.bodies.size(); ++b) {
    if (model.bodies[b].kind != BodyKind::kRigid3d) continue;
    rotational[b] = Eigen::SelfAdjointEigenSolver<Mat3<double>>(PrincipalInertia(model.bodies[b])).operatorInverseSqrt();
  }
  Eigen::MatrixXd scaled = Eigen::MatrixXd::Zero(check.constraint_rows, check.coordinates);
  for (int i = 0; i < check.constraint_rows; ++i) {
    for (const BodyVector<double>* g : {&rows[i].a, &rows[i].b}) {
      if (g->body == kWorld) continue;
      const Body<double>& body = model.bodies[g->body];
      const int o = body.v_offset;
      for (int k = 0; k < model.dimension; ++k) scaled(i, o + k) += g->translation[k] / std::sqrt(body.mass);
      if (body.kind == BodyKind::kPlanar) scaled(i, o + 2) += g->rotation[2] / std::sqrt(body.inertia);
      if (body.kind == BodyKind::kRigid3d) scaled.block<1, 3>(i, o + 3) += (rotational[g->body] * g->rotation).transpose();
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
