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
// Joint limits: each limited joint's coordinate at the assembled start, its range, and which side is active
// there (resting on its bound and pressed into it: the run starts with that side's row). Contact: every pair of
// shapes the pair rules let touch (contact_geometry.h), its smallest gap at the assembled start and whether it
// touches there (a feature within kTouching of zero, or held: the run starts with its row).
// The initial violation is the largest constraint violation at the initial state, before assembly; the assembly
// error is what Simulate would refuse the scene with (AssembledInitialState, simulator.h), empty when it
// assembles.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "tether/dynamics/model/model.h"

namespace tether {

inline constexpr double kRankTolerance = 1e-10;
// Above this many rows the dense SVD (O(rows^2 coordinates) time, a dense matrix in memory) gives way to
// SuiteSparseQR of (J M^-1/2)^T (a column whose remaining norm is below kRankTolerance times the largest column
// norm counts as dependent and is moved to the end): its rank and the rows it moves are the rank and the
// redundant rows, and the condition number is estimated from the Schur complement of the rows it keeps,
// sqrt(lambda_max / lambda_min) by power and inverse iteration (a lower bound: 0.4% low on a chain of 1100 links,
// whose largest eigenvalues cluster, after 100 iterations each).
inline constexpr int kDenseCheckRows = 1000;

struct LimitCheck {
  int constraint = 0;      // scene index
  std::string name;        // the joint's name ("" when it has none)
  std::string coordinate;  // "angle" or "displacement"
  double start = 0.0;      // the coordinate at the assembled start, rad or m
  bool has_low = false, has_high = false;
  double low = 0.0, high = 0.0;
  bool low_active = false, high_active = false;
};

struct ContactCheck {
  std::string pair;              // "A|B", the shapes' labels
  int shape_a = 0, shape_b = 0;  // scene indices
  double gap = 0.0;              // the smallest of its features' gaps at the assembled start, m
  bool touching = false;
};

struct SceneCheck {
  int coordinates = 0;  // velocity coordinates (v's size)
  int constraint_rows = 0;
  int rank = 0;
  int degrees_of_freedom = 0;
  std::vector<int> redundant_constraints;  // scene indices of constraints with a row that adds nothing
  double initial_violation = 0.0;          // m
  int worst_constraint = -1;               // scene index of the largest initial violation
  double condition_number = 1.0;           // of J M^-1/2 over its rank
  bool condition_estimated = false;        // from the sparse QR's R (kDenseCheckRows)
  std::string solver;                      // the KKT path the scene takes: dense, sparse or (auto only) tree
  std::string assembly_error;              // empty when the initial state can be assembled
  std::vector<LimitCheck> limits;          // in scene order (when the scene assembles)
  std::vector<ContactCheck> contacts;      // the pairs, in scene order (when the scene assembles)
};

SceneCheck CheckScene(const Model<double>& model);

// `tether check --json` (and the Python module's check): the fields above by name, `worst_constraint` only where
// there is one, `assembles`, `assembly_error` where it is not empty, and `limits` (each with `constraint`, `name`,
// `coordinate`, `start`, `range` with null for an open side, and `active`: "low", "high" or null), and `contacts`
// (each with `pair`, `shapes` [a, b], `gap` and `touching`).
nlohmann::json SceneCheckJson(const SceneCheck& check);

}  // namespace tether
