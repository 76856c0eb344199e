// Solving the Schur system S x = b of schur_system.h (regularized only near dependent rows), for double and Jet
// scalars.
//
// Two factorizations of the double matrix, chosen by KktSolver:
//   kSparse  LDL^T in a breadth-first or minimum-degree order (sparse_ldlt.h), whose symbolic analysis is
//            done once per solver (per run) and only the numeric factorization per solve. For a chain the
//            ordering keeps S banded and the cost is linear in its length;
//   kDense   Cholesky (LLT) of S held as a dense matrix: a reference path, and a fallback for a user who wants
//            to compare.
// kAuto is kSparse: measured with bench/chain_bench.cc, it is faster than kDense at every size from one row up
// (0.49 against 0.88 us per rk4 step of a one-particle chain, 4.0 against 5.7 us of the four-bar;
// studies/scaling), except where its factor is one dense block: a hub body couples every pair of the rows that
// act on it (MuJoCo's softbox: 218 prismatic joints on one body, 1090 rows), and the sparse factorization's
// scalar updates (n^3 / 6 of them) then take five times as long as Eigen's blocked Cholesky (a 0.01 s run of
// the softbox: 3.2 s against 0.63 s). kAuto takes kDense from kDenseBlockRows rows up where the sparse
// factorization would make more than n^3 / 24 updates, a quarter of a dense block's.
//
// Jets (the implicit function theorem): with S = S0 + sum_k dS_k e_k and b = b0 + sum_k db_k e_k,
//   x0 = S0^-1 b0,   dx_k = S0^-1 (db_k - dS_k x0),
// so the double matrix S0 is factored once and every derivative direction costs one more pair of triangular
// solves. The right-hand sides db_k - dS_k x0 are the derivative parts of the Jet residual b - S x0.
// Factoring the matrix of Jets itself (same dense or sparse method, in Jet arithmetic) is kept only as a test
// oracle and a benchmark baseline (factor_jet_matrices).
//
// Conditioning. Every factorization S = P^T L D L^T P (D = diag(L)^2 for the dense Cholesky) also reveals how
// close the rows are to dependence: the pivot ratio d_i / S_ii (ordered as the factorization orders the rows) is
// sin^2 of the angle, in the M^-1 metric, between row i's Jacobian and the span of the rows before it.
//
// Regularization only where it is needed. S itself is factored first; where every pivot ratio is at least
// kNearSingularPivotRatio that factorization is the one solved with, exactly. Otherwise (a ratio below it, a
// zero or negative pivot, a failed Cholesky) the regularized S + eps D of schur_system.h is factored instead, and
// its ratios are read: one below kNearSingularPivotRatio but above kRedundantPivotRatio marks a configuration
// near a singular one (a mechanism at a dead centre or a bifurcation, a light body between nearly collinear
// rods), which the solver records and after which the simulator projects the state back onto the constraints
// (simulator.cc); ratios at the regularization's floor belong to exactly redundant rows, whose least-norm
// multipliers the regularization gives. Near a singular configuration the regularized solution is also the
// wanted one: it damps the nearly dependent direction that carries a mechanism through it (a four-bar's
// unstabilized singular pass diverges without).
// Why not always regularize: the regularized solution meets S x = b - eps D x, and where one S_ii dwarfs the
// others (a thin rod's spin, S_ii ~ 1 / I_axial) eps S_ii lambda_i is a constraint acceleration error that no
// step size removes (a four-rod hinge chain drifted off its hinges by 2.5e-8 m in 1 s without stabilization).
// What it costs: a scene whose rows stay redundant would factor twice per solve, so after a regularized solve the
// next one factors S + eps D first, and S again only where that one turns out well conditioned.
// Singular passes. Within the near-singular stretch of a mechanism passing a singular configuration, the rows
// losing rank have pivot ratios ~ theta^2 (theta its distance from the configuration, in radians for a
// linkage), so a stage state off the constraints by delta (an integrator's stage is, by O(h^2)) gets a
// multiplier ~ delta / theta^2 in the near-dependent direction, whose force leaks ~ delta^2 / theta^2 into the
// motion: within 1e-5 rad of an IFToMM A02 linkage's horizontal pass, a velocity error of 4e-3 rad/s. A step
// whose factorizations saw a near-singular ratio and one below kSingularPassRatio (within ~1e-3 rad of the pass;
// saw_singular_pass) is retaken by the simulator in substeps with the pivot floor on (set_pass_floor): every pivot
// below kPassPivotFloor S_jj is raised to it (sparse_ldlt.h), which bounds that multiplier and leaves the rows away
// from dependence exact; exactly redundant rows then get a basic rather than the least-norm split of their
// multipliers for those substeps (the motion is the same). The dense path has no floor. Both marks were chosen on
// A02 with N = 20, 39, 40 and 41 parallelograms and steps of 0.8, 1 and 1.25 ms (docs/numerics.md, "Steps that
// come close to the pass"): a lower detection mark lets steps with stages 1e-4 rad from the pass through
// unrefined (6e-5 rad lost at 0.8 ms), and a floor at 1e-6 loses accuracy where a scene stays near singular (a
// humanoid whose ball joints were split into hinges, read as near singular at every step before light bodies were
// told apart, below).
// Light bodies. The ratio d_i / S_ii is also small where one light body dominates S_ii and the rows before i
// hold that body already: a split joint's intermediate body of 1e-6 of a body's mass between two hinges, a light
// particle between two heavy ones. The nearly lost direction then moves the heavier bodies at their own scale
// (for two rows through a light body K between A and B, d_i ~ g_A M_A^-1 g_A + g_B M_B^-1 g_B), so it is no
// singular configuration and no multiplier grows in it: such a scene was projected and had every step retaken in
// substeps (a split humanoid took 22 times as long, for the same motion to 4e-13 m). So a small ratio is read again
// against the row's smallest body share s_i (SchurSource::SmallestShare: the share of S_ii its heaviest body
// brings, the whole of S_ii for a row on one body): the row counts as near dependence only where d_i is also small
// against min(S_ii, kLightShareSpread s_i). Rows whose bodies' shares lie within kLightShareSpread of each other
// are read exactly as before (the shipped scenes and the imported humanoid run bit for bit as they did); the
// redundant mark stays relative to S_ii, where the regularization puts its floor. Asked only of rows whose ratio
// is small, it costs nothing elsewhere.
// For Jets the value part decides, and the derivative parts are solved with the same matrix (a floor's E is a
// constant).
#pragma once

#include <Eigen/Cholesky>
#include <Eigen/SparseCore>
#include <memory>
#include <type_traits>
#include <vector>

#include "tether/dynamics/solvers/schur_system.h"
#include "tether/dynamics/solvers/sparse_ldlt.h"

namespace tether {

inline constexpr double kNearSingularPivotRatio = 1e-4;
inline constexpr double kRedundantPivotRatio = 1e-9;
inline constexpr double kSingularPassRatio = 1e-6;
inline constexpr double kPassPivotFloor = 1e-8;
inline constexpr double kLightShareSpread = 1e3;

inline constexpr int kDenseBlockRows = 128;

// The path a request takes, given the sparse analysis of its pattern: kAuto becomes kSparse or kDense (above).
KktSolver ResolveSolver(KktSolver requested, const SparseLdlt& analysis);

// What the solver carries from one step of a run to the next (a checkpoint's part of it, stepper.h): whether the
// next factorization starts from S + eps D (after a regularized one). Plain data, the same for every scalar.
struct SolverMemory {
  bool starts_regularized = false;
};

class SchurSolver {
 public:
  // Analyzes the pattern once; `kind` may be kAuto (kind() is then the path taken).
  SchurSolver(const SchurPattern& pattern, KktSolver kind, bool factor_jet_matrices = false);

  KktSolver kind() const { return kind_; }
  // Stores `pattern` (the one this solver was made with) in the order the sparse factorization reads it, so that
  // a factorization starts from one block copy of S (sparse_ldlt.h); nothing where the path is dense.
  void StoreInFactorOrder(SchurPattern* pattern);

  // Whether a factorization since the last call to ForgetConditioning() was near a singular configuration.
  bool saw_near_singular() const { return saw_near_singular_; }
  void ForgetConditioning() { saw_near_singular_ = false; }
  // Whether the factorizations since the last ForgetSingularPass() came close to a singular pass (above).
  bool saw_singular_pass() const { return pass_near_singular_ && pass_close_; }
  void ForgetSingularPass() { pass_near_singular_ = pass_close_ = false; }
  bool was_close_to_pass() const { return close_to_pass_; }  // the last factorization: a ratio below kSingularPassRatio
  // Floors the pivots of regularized factorizations at kPassPivotFloor S_jj (sparse path), or stops.
  void set_pass_floor(bool on) { pass_floor_ = on; }

  // Whether the next factorization starts from S + eps D (after a regularized one): state a replayed step restores.
  bool starts_regularized() const { return regularized_; }
  SolverMemory memory() const { return {regularized_}; }
  void Restore(const SolverMemory& memory) { regularized_ = memory.starts_regularized; }
  // What a solve leaves behind, as a replay that skips a solve it knows the outcome of sets it (kkt_log.h).
  void RestoreConditioning(bool regularized, bool near_singular, bool close_to_pass) {
    regularized_ = regularized;
    NoteConditioning(near_singular, close_to_pass);
  }

  // x = S^-1 b, S given by its stored values (AssembleSchur from `source`). Returns false, leaving x unchanged,
  // when the factorization fails (a non-finite or indefinite matrix: the run is diverging).
  template <typename T>
  bool Solve(const std::vector<T>& values, const VecX<T>& b, VecX<T>* x, const SchurSource<T>& source);
  // The same after a Solve with the same values: in double a further right-hand side costs a back substitution,
  // not a factorization (Jets and Rev, whose solves carry the derivatives of S, solve again).
  template <typename T>
  bool SolveAgain(const std::vector<T>& values, const VecX<T>& b, VecX<T>* x, const SchurSource<T>& source) {
    if constexpr (std::is_same_v<T, double>) {
      *x = b;
      SolveInPlace(x);
      return true;
    } else {
      return Solve(values, b, x, source);
    }
  }

  // After a Solve in double: b <- F^-1 b with S = F F^T (the factorization's: F = P^T L D^1/2, or the Cholesky
  // factor), so that b^T S^-1 b' is the dot product of two such; false where the factorization has no such F.
  bool HalfSolveInPlace(Eigen::VectorXd* b);

  // The factorization the last Solve used (of S, or of S + eps D where it regularized), kept to solve with again
  // after later ones: an adjoint sweep's solve with a recorded evaluation's matrix (S is symmetric).
  struct Factorization {
    SparseLdlt::Numeric sparse;
    Eigen::LLT<Eigen::MatrixXd> dense;
  };
  void SaveFactorization(Factorization* factorization) const;
  // x = A^-1 x with a saved factorization of A.
  void SolveWith(const Factorization& factorization, Eigen::VectorXd* x);

 private:
  // Factors S, or S + eps D where S's rows are close to dependence (above); regularized_ says which.
  template <typename T>
  bool Factor(const std::vector<double>& values, const SchurSource<T>& source);
  // Factors `values` as given (with SparseLdlt's pivot floor); false on a failed factorization.
  bool FactorAsGiven(const std::vector<double>& values, double pivot_floor = 0.0);
  // Over the last factorization of `values`: whether every pivot ratio is at least kNearSingularPivotRatio (read
  // against the light bodies' scale where it is not, above), and (with note_near_singular) records a ratio between
  // the redundant and the near-singular marks.
  template <typename T>
  bool WellConditioned(const std::vector<double>& values, bool note_near_singular, const SchurSource<T>& source);
  void NoteConditioning(bool near_singular, bool close_to_pass) {
    close_to_pass_ = close_to_pass;
    saw_near_singular_ = saw_near_singular_ || near_singular;
    pass_near_singular_ = pass_near_singular_ || near_singular;
    pass_close_ = pass_close_ || close_to_pass;
  }
  void SolveInPlace(Eigen::VectorXd* x);
  // The values of the matrix factored last: `values` itself, or regularized_jets_ after a regularized factorization.
  const std::vector<Jet>& FactoredJets(const std::vector<Jet>& values);
  bool SolveByFactoringJets(const std::vector<Jet>& values, const VecX<Jet>& b, VecX<Jet>* x,
                            const SchurSource<Jet>& source);

  const SchurPattern* pattern_;
  KktSolver kind_;
  Eigen::MatrixXd dense_;
  Eigen::LLT<Eigen::MatrixXd> dense_factor_;
  SparseLdlt sparse_factor_;
  Eigen::VectorXd pivots_;
  bool saw_near_singular_ = false;
  bool pass_near_singular_ = false, pass_close_ = false, close_to_pass_ = false;
  bool pass_floor_ = false;
  bool regularized_ = false;  // the last factorization was of S + eps D (it starts the next attempt)
  std::vector<double> regularized_values_;
  std::vector<Jet> regularized_jets_;
  // scratch for the Jet path
  std::vector<double> value_part_;
  Eigen::VectorXd x0_, column_;
  Eigen::Matrix<double, Eigen::Dynamic, kJetStride, Eigen::RowMajor> columns_;  // a Jet's derivative parts
  VecX<Jet> product_;
  // the oracle path
  bool factor_jet_matrices_;
  Eigen::Matrix<Jet, Eigen::Dynamic, Eigen::Dynamic> jet_dense_;
  Eigen::SparseMatrix<Jet> jet_sparse_;
};

}  // namespace tether
