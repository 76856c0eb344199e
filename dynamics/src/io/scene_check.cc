#include "tether/dynamics/io/scene_check.h"

#include <Eigen/Eigenvalues>
#include <Eigen/QR>
#include <Eigen/SPQRSupport>
#include <Eigen/SVD>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <stdexcept>

#include "tether/dynamics/constraints/constraint_rows.h"
#include "tether/dynamics/effects/effects.h"
#include "tether/dynamics/integration/simulator.h"
#include "tether/dynamics/integration/stepper.h"
#include "tether/dynamics/model/errors.h"
#include "tether/dynamics/solvers/schur_solver.h"
#include "tether/dynamics/solvers/tree_elimination.h"

namespace tether {
namespace {

// sqrt(lambda_max / lambda_min) of S = A A^T over the kept rows of A: the Rayleigh quotients after
// kConditionIterations of power iteration (the largest eigenvalue) and of inverse iteration with a sparse LDL^T
// of S (the smallest), from a fixed start.
constexpr int kConditionIterations = 100;
double EstimatedCondition(const Eigen::SparseMatrix<double>& a, const std::vector<bool>& kept) {
  std::vector<Eigen::Triplet<double>> selection;
  for (int i = 0, k = 0; i < a.rows(); ++i) {
    if (kept[i]) selection.emplace_back(k++, i, 1.0);
  }
  Eigen::SparseMatrix<double> select(static_cast<int>(selection.size()), a.rows());
  select.setFromTriplets(selection.begin(), selection.end());
  const Eigen::SparseMatrix<double> rows = select * a;
  const Eigen::SparseMatrix<double> schur = rows * rows.transpose();
  if (schur.rows() == 0) return 1.0;
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> factor(schur);
  if (factor.info() != Eigen::Success) return INFINITY;
  const Eigen::VectorXd start = Eigen::VectorXd::LinSpaced(schur.rows(), 1.0, 2.0).normalized();
  Eigen::VectorXd up = start, down = start;
  double largest = 0.0, smallest_inverse = 0.0;     // of S and of S^-1
  for (int k = 0; k < kConditionIterations; ++k) {  // Rayleigh quotients of the normalized iterates
    up = (schur * up).normalized();
    down = factor.solve(down).normalized();
  }
  largest = up.dot(schur * up);
  smallest_inverse = down.dot(factor.solve(down));
  return std::sqrt(largest * smallest_inverse);
}

// The limited joints and the contact pairs at the start of a run; assembles the initial state once (InputError
// when it cannot), by the stepper where there are limits or shapes (its start resolves them).
void CheckGaps(const Model<double>& model, SceneCheck* check) {
  if (!HasJointLimits(model) && model.shapes.empty()) {
    RunReport report;
    AssembledInitialState(model, &report);
    return;
  }
  Stepper<double> stepper(model, RunOptions{}, [](const Sample<double>&) {});
  std::vector<LimitCheck>& out = check->limits;
  const UnilateralEvents<double>& sides = stepper.gaps();
  const ContactGeometry& contacts = sides.contacts();
  for (const ContactPair& pair : contacts.pairs) {
    check->contacts.push_back({pair.label, pair.a, pair.b, std::numeric_limits<double>::infinity(), false});
  }
  const State<double>& start = stepper.state();
  BodyFrames<double> frames;
  UpdateFrames(model, start.q, start.v, false, &frames);
  for (int i = 0; i < sides.size(); ++i) {
    const auto& side = sides.side(i);
    if (side.feature >= 0) {
      const ContactFeature& feature = contacts.features[side.feature];
      ContactCheck& pair = check->contacts[feature.pair];
      const double gap = FeatureGapValue(model, feature, frames, start.q);
      pair.gap = std::min(pair.gap, gap);
      pair.touching = pair.touching || sides.active(i) || gap <= kTouching;
      continue;
    }
    const Joint<double>& joint = model.joints[side.joint];
    if (out.empty() || out.back().constraint != joint.scene_index) {
      LimitCheck c;
      c.constraint = joint.scene_index;
      c.name = joint.name;
      c.coordinate = LimitedCoordinate(JointKindOf(joint.type)) == JointCoordinate::kAngle ? "angle" : "displacement";
      c.start = stepper.coordinates().last[side.coordinate];
      c.has_low = joint.range.has_low;
      c.has_high = joint.range.has_high;
      c.low = joint.range.low;
      c.high = joint.range.high;
      out.push_back(c);
    }
    (side.side > 0 ? out.back().low_active : out.back().high_active) = sides.active(i);
  }
}

}  // namespace

SceneCheck CheckScene(const Model<double>& model) {
  SceneCheck check;
  const State<double> start = InitialState(model);
  const ConstraintSet<double> set = BuildConstraintSet(model, start.q);
  const std::vector<RowInfo> infos = DescribeRows(model, set);
  std::vector<ConstraintRow<double>> rows(infos.size());
  check.coordinates = model.NumVelocities();
  check.constraint_rows = static_cast<int>(rows.size());
  const std::vector<BodyLayout> layout = LayoutOf(model);
  const SchurPattern pattern(infos, layout);
  check.solver = SchurSolver(pattern, model.simulation.solver).kind() == KktSolver::kDense ? "dense" : "sparse";
  if (model.simulation.solver == KktSolver::kAuto && TreePlan::Of(infos, layout, DoubleHingesByScene(model.joints))) {
    check.solver = "tree";
  }
  check.degrees_of_freedom = check.coordinates;
  try {
    CheckGaps(model, &check);
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

  // J M^-1/2, from the rows' body blocks
  std::vector<Mat3<double>> rotational(model.bodies.size());  // I_P^-1/2 of 3D bodies
  for (size_t b = 0; b < model.bodies.size(); ++b) {
    if (model.bodies[b].kind != BodyKind::kRigid3d) continue;
    rotational[b] =
        Eigen::SelfAdjointEigenSolver<Mat3<double>>(PrincipalInertia(model.bodies[b])).operatorInverseSqrt();
  }
  std::vector<Eigen::Triplet<double>> entries;
  for (int i = 0; i < check.constraint_rows; ++i) {
    for (const BodyVector<double>* g : {&rows[i].a, &rows[i].b}) {
      if (g->body == kWorld) continue;
      const Body<double>& body = model.bodies[g->body];
      const int o = body.v_offset;
      for (int k = 0; k < model.dimension; ++k)
        entries.emplace_back(i, o + k, g->translation[k] / std::sqrt(body.mass));
      if (body.kind == BodyKind::kPlanar) entries.emplace_back(i, o + 2, g->rotation[2] / std::sqrt(body.inertia));
      if (body.kind == BodyKind::kRigid3d) {
        const Vec3<double> r = rotational[g->body] * g->rotation;
        for (int k = 0; k < 3; ++k) entries.emplace_back(i, o + 3 + k, r[k]);
      }
    }
  }
  Eigen::SparseMatrix<double> scaled(check.constraint_rows, check.coordinates);
  scaled.setFromTriplets(entries.begin(), entries.end());  // sums the two blocks of a row on one body
  std::vector<int> left_out;                               // rows the rank-revealing QR puts after the rank
  if (check.constraint_rows <= kDenseCheckRows) {
    const Eigen::MatrixXd dense(scaled);
    const Eigen::JacobiSVD<Eigen::MatrixXd> svd(dense);
    const Eigen::VectorXd sigma = svd.singularValues();
    const double largest = sigma.size() ? sigma[0] : 0.0;
    while (check.rank < sigma.size() && sigma[check.rank] > kRankTolerance * largest) ++check.rank;
    check.condition_number = check.rank ? largest / sigma[check.rank - 1] : 1.0;
    const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(dense.transpose());
    for (int k = check.rank; k < check.constraint_rows; ++k) left_out.push_back(qr.colsPermutation().indices()[k]);
  } else {
    const Eigen::SparseMatrix<double> transposed = scaled.transpose();
    double largest_norm = 0.0;
    for (int j = 0; j < transposed.outerSize(); ++j) largest_norm = std::max(largest_norm, transposed.col(j).norm());
    Eigen::SPQR<Eigen::SparseMatrix<double>> qr;
    qr.setPivotThreshold(kRankTolerance * largest_norm);
    qr.compute(transposed);
    if (qr.info() != Eigen::Success)
      throw std::runtime_error("tether check: SuiteSparseQR failed on the constraint rows");
    check.rank = static_cast<int>(qr.rank());
    std::vector<bool> kept(check.constraint_rows, true);
    for (int k = check.rank; k < check.constraint_rows; ++k) {
      left_out.push_back(qr.colsPermutation().indices()[k]);
      kept[left_out.back()] = false;
    }
    check.condition_number = EstimatedCondition(scaled, kept);
    check.condition_estimated = true;
  }
  check.degrees_of_freedom = check.coordinates - check.rank;
  std::set<int> redundant;
  for (int row : left_out) redundant.insert(infos[row].scene_index);
  check.redundant_constraints.assign(redundant.begin(), redundant.end());
  return check;
}

nlohmann::json SceneCheckJson(const SceneCheck& c) {
  nlohmann::json out = {{"coordinates", c.coordinates},
                        {"constraint_rows", c.constraint_rows},
                        {"rank", c.rank},
                        {"degrees_of_freedom", c.degrees_of_freedom},
                        {"redundant_constraints", c.redundant_constraints},
                        {"initial_violation", c.initial_violation},
                        {"condition_number", c.condition_number},
                        {"condition_estimated", c.condition_estimated},
                        {"solver", c.solver}};
  if (c.worst_constraint >= 0) out["worst_constraint"] = c.worst_constraint;
  out["assembles"] = c.assembly_error.empty();
  if (!c.assembly_error.empty()) out["assembly_error"] = c.assembly_error;
  out["limits"] = nlohmann::json::array();
  for (const LimitCheck& l : c.limits) {
    const nlohmann::json low = l.has_low ? nlohmann::json(l.low) : nlohmann::json(nullptr);
    const nlohmann::json high = l.has_high ? nlohmann::json(l.high) : nlohmann::json(nullptr);
    const nlohmann::json active = l.low_active    ? nlohmann::json("low")
                                  : l.high_active ? nlohmann::json("high")
                                                  : nlohmann::json(nullptr);
    out["limits"].push_back({{"constraint", l.constraint},
                             {"name", l.name},
                             {"coordinate", l.coordinate},
                             {"start", l.start},
                             {"range", {low, high}},
                             {"active", active}});
  }
  out["contacts"] = nlohmann::json::array();
  for (const ContactCheck& contact : c.contacts) {
    out["contacts"].push_back({{"pair", contact.pair},
                               {"shapes", {contact.shape_a, contact.shape_b}},
                               {"gap", contact.gap},
                               {"touching", contact.touching}});
  }
  return out;
}

}  // namespace tether
