// A static look at a scene's constraints in its initial state, for `tether check`.
//
// With J the constraint Jacobian (rows x velocities) at the initial state and M the mass matrix, the singular values of
// J M^-1/2 tell what the KKT solve will face:
//   rank r      the number of singular values above kRankTolerance times the largest,
//   dof         velocities - r (degrees of freedom of the mechanism there: the Bricard linkage, which
//               Grubler's count calls rigid, has one),
//   redundant   rows - r rows add nothing; a rank-revealing (column-pivoted) QR of (J M^-1/2)^T names the
//               constraints whose rows it leaves out after the first r pivots (one valid choice of rows to drop),
//   condition   largest / smallest of the r singular values kept (the conditioning of the Schur complement
//               S = J M^-1 J^T is its square).
// The initial violation is the largest constraint violation at the initial state, before assembly; the assembly
// error is what Simulate would refuse the scene with (AssembledInitialState, simulator.h), empty when it
// assembles.
#pragma once

#include <string>
#include <vector>

#include "tether/dynamics/model.h"

namespace tether {

inline constexpr double kRankTolerance = 1e-10;

struct SceneCheck {
  int coordinates = 0;                     // velocity coordinates (v's size)
  int constraint_rows = 0;
  int rank = 0;
  int degrees_of_freedom = 0;
  std::vector<int> redundant_constraints;  // scene indices of constraints with a row that adds nothing
  double initial_violation = 0.0;          // m
  int worst_constraint = -1;               // scene index of the largest initial violation
  double condition_number = 1.0;           // of J M^-1/2 over its rank
  std::string solver;                      // the KKT path `auto` picks: dense or sparse
  std::string assembly_error;              // empty when the initial state can be assembled
};

SceneCheck CheckScene(const Model<double>& model);

}  // namespace tether
