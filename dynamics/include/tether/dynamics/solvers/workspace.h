// Workspace<T>: everything a run computes into, made once per run so that a step allocates nothing
// (Pinocchio's Model/Data split). It holds the run's constraint primitives (their fixed quantities taken at the
// start), the row layout, the Schur pattern and its factorization (analyzed once), M^-1, the joint coordinates,
// the bodies' frames at the last evaluation, the gains in use, and the KKT system's vectors. (The integrator keeps
// its own stages: TimeIntegrator, integrators.h.)
// With joint limits the rows change at events (unilateral_events.h): each set of active limits the run meets gets its
// pattern and solver once (SchurShape), kept for the run, so that a set met again costs no analysis and a Rev
// record of a KKT solve keeps the solver it was made with. (One pattern of every possible row with the inactive
// ones masked was the other way; it would make every step of a limited scene eliminate rows it does not have,
// where this way a step with no active limit factors exactly the matrix of the scene without limits.)
#pragma once

#include <memory>
#include <utility>
#include <vector>

#include "tether/dynamics/constraints/constraint_rows.h"
#include "tether/dynamics/constraints/contact_friction.h"
#include "tether/dynamics/constraints/joint_coordinates.h"
#include "tether/dynamics/solvers/kkt_log.h"
#include "tether/dynamics/solvers/schur_solver.h"
#include "tether/dynamics/solvers/tree_elimination.h"

namespace tether {

// M^-1 for the model's mass matrix, block diagonal by body and diagonal in its translations and planar angles.
template <typename T>
struct InverseMass {
  VecX<T> diagonal;                 // per velocity: 1/m, 1/I (planar); zero on a 3D body's rotation
  std::vector<Mat3<T>> rotational;  // per body: I_P^-1 of a 3D rigid body (zero for the others)
};

template <typename T>
InverseMass<T> BuildInverseMass(const Model<T>& model);

// *out = M^-1 x (v-shaped); out may alias x. The model gives the bodies' layout only, so its scalar S may differ
// from the values' T (the recorded KKT solve computes in double for a Model<Rev>).
template <typename S, typename T>
void ApplyInverseMass(const Model<S>& model, const InverseMass<T>& inverse, const VecX<T>& x, VecX<T>* out);

// What one KKT solve computes into (ComputeAcceleration, the projection), sized once per run.
template <typename T>
struct KktSystem {
  KktSystem(const SchurPattern& pattern, int nv);

  std::vector<T> schur;             // S at the last evaluation (pattern.nonzeros())
  std::vector<T> assembly_scratch;  // AssembleSchur's dense products
  VecX<T> rhs, lambda;              // Schur right-hand side and multipliers (size m)
  VecX<T> u_plus_alpha_v;           // M^-1 f + alpha v: J of it serves the Schur right-hand side (size nv)
};

// The Schur pattern of one row layout and its solver (which points into it), at a fixed address; and where the
// layout is a tree and the solver is left to tether (KktSolver::kAuto), its elimination plan (tree_elimination.h),
// which the evaluations take first.
struct SchurShape {
  // double_hinges: DoubleHingesByScene of the model's joints
  SchurShape(const std::vector<RowInfo>& infos, const std::vector<BodyLayout>& layout,
             const std::vector<int>& double_hinges, KktSolver kind, bool factor_jet_matrices)
      : pattern(infos, layout),
        solver(pattern, kind, factor_jet_matrices),
        tree(kind == KktSolver::kAuto ? TreePlan::Of(infos, layout, double_hinges) : std::nullopt) {
    solver.StoreInFactorOrder(&pattern);
  }
  SchurShape(const SchurShape&) = delete;
  SchurShape& operator=(const SchurShape&) = delete;
  SchurPattern pattern;
  SchurSolver solver;
  std::optional<TreePlan> tree;
};

// Every row layout's pattern and solver met in a run, by its active sides (unilateral_events.h).
using SchurShapes = std::vector<std::pair<std::vector<int>, std::unique_ptr<SchurShape>>>;

template <typename T>
struct Workspace {
  // `q_start` fixes the constraints' quantities taken at the start (model.h); factor_jet_matrices: see
  // RunOptions (a test oracle; the default applies the implicit function theorem).
  Workspace(const Model<T>& model, const VecX<T>& q_start, bool factor_jet_matrices = false);
  Workspace(const Workspace&) = delete;  // pattern and solver point into shapes
  Workspace& operator=(const Workspace&) = delete;

  // Replaces the active joint limits and contacts (the last rows, unilateral_events.h) and what the rows shape:
  // the row layout, the Schur pattern and its solver (from `shapes`, analyzed the first time the set is met, which
  // `key` names), the rows and the KKT system. Taken at events only (it allocates).
  void SetActiveGaps(const Model<T>& model, const std::vector<LimitPrimitive<T>>& limits,
                     const std::vector<ContactPrimitive>& contacts, const std::vector<int>& key);

  ConstraintSet<T> constraints;      // the run's constraint primitives
  std::vector<RowInfo> infos;        // one per constraint row
  std::vector<BodyLayout> layout;    // the bodies' kinds and velocity offsets, compact
  bool factor_jet_matrices = false;  // RunOptions::factor_jet_matrices, for the solvers SetActiveGaps makes
  SchurShapes shapes;                // the first without active limits
  SchurPattern* pattern;             // of S = J M^-1 J^T for the current rows (in shapes)
  SchurSolver* solver;               // its factorization
  const TreePlan* tree;              // the current rows' tree elimination (in shapes), or nullptr
  InverseMass<T> inverse_mass;
  std::vector<Mat3<T>> principal_inertia;  // of each body (PrincipalInertias), for the gyroscopic torques
  JointCoordinates<T> coordinates;  // from q_start; the Stepper builds them again from the assembled state
  T alpha = T(0.0), beta = T(0.0);  // Baumgarte gains in use (0 unless the method is baumgarte)

  BodyFrames<T> frames;                // at the last evaluation
  std::vector<ConstraintRow<T>> rows;  // rows at the last evaluation
  std::vector<SlidingRow<T>> sliding;  // the sliding contacts' friction at the last evaluation (contact_friction.h)
  int painleve = -1;                   // the sliding contact's row where a solve met Painleve's paradox, or -1
  KktSystem<T> kkt;                    // S, its right-hand side and the multipliers at the last solve
  TreeWork<T> tree_work;               // the tree elimination's blocks at the last evaluation that took it
  VecX<T> force;                       // generalized force f (size nv)
  VecX<T> reaction;                    // M^-1 J^T lambda (size nv)
  // The adjoint's log of a step's KKT solves (kkt_log.h), or nullptr: a double run keeps its solves there, a
  // recorded replay takes them back.
  KktLog* kkt_log = nullptr;

  VecX<T> projection_q;  // the projection's target q_t (projection.h)
};

// ws->kkt.schur from ws->rows.
template <typename T>
void AssembleSchur(Workspace<T>* ws);

// What AssembleSchur(ws) assembles ws->kkt.schur from, for the solver's conditioning test.
template <typename T>
SchurSource<T> SchurSourceOf(const Workspace<T>& ws) {
  return {ws.layout, ws.rows, ws.inverse_mass.diagonal, ws.inverse_mass.rotational};
}

// ws->kkt.rhs = J x for the rows in ws (x v-shaped).
template <typename T>
void MultiplyJacobian(const Model<T>& model, const VecX<T>& x, Workspace<T>* ws);

// *out = M^-1 J^T ws->kkt.lambda for the rows in ws.
template <typename T>
void ApplyReaction(const Model<T>& model, Workspace<T>* ws, VecX<T>* out);

// Rows (and frames) at (q, v) into ws->rows.
template <typename T>
void EvaluateRows(const Model<T>& model, const VecX<T>& q, const VecX<T>& v, bool velocity_terms, Workspace<T>* ws);

}  // namespace tether
