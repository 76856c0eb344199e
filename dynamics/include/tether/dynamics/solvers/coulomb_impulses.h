// Coulomb's impulse problem of a time step (the scene's "contact": "stepping", unilateral_stepping.cc): impulses p
// on rows grouped in blocks (a contact's gap row and its 0 to 2 slip rows, or a joint limit's one row) such that,
// with W the Delassus matrix, u the rates before and b the targets, the rates after y = u + W p - b meet
//   gap row    p_n >= 0,  y_n >= 0,  p_n y_n = 0
//   slip rows  |p_t| <= mu p_n,  y_t = -c p_t with c >= 0 and c (mu p_n - |p_t|) = 0
// (a side apart, held, sticking, or sliding with the impulse mu p_n against its slip after: Coulomb's exact cone).
//
// They are the root of Alart and Curnier's function, block by block (rho_n = 1 / W_nn, rho_t = 1 / max_t W_tt):
//   F_n = p_n - max(0, a),                a = p_n - rho_n y_n
//   F_t = p_t - P(p_t - rho_t y_t, mu max(0, a)),   P(z, R) = z min(1, R / |z|) (the projection on the disc)
// F = 0 exactly where the conditions above hold. F is piecewise smooth, so Newton's method with an element of its
// generalized Jacobian converges quadratically near a solution: from the last step's impulses one or two
// iterations where the contacts persist. A backtracking (Armijo) line search on |S F|^2, S = diag(1 / rho) (rates
// in m/s or rad/s), globalizes it; where it stalls anyway (Coulomb's problem is not monotone: |S F|^2 has minima
// that are not solutions) projected Gauss-Seidel sweeps move the iterate before Newton goes on.
//
// Several contacts along one plane (a box's four corners) make W singular: the motion is unique, the impulses are
// not, and neither is Newton's step. The steps on the problem itself are taken with W + eps diag(W) in the Jacobian
// (eps = kImpulseRegularization), F itself with W, so that the conditions hold exactly where they converge. Where
// the line search refuses such a step (a long one along W's null space: a humanoid's feet, four capsule ends on the
// floor, 12 rows of rank 6, and targets no rigid motion meets), the problem is degenerate: the steps from then on
// take W + 1e-3 diag(W), bounded, which converge linearly, and the solve accepts the coarser `acceptable` accuracy
// (Solve's caller states it; a solve may also be told that its problem is degenerate from the start, where the last
// step's was). Where even those stall, proximal steps follow: each solves the problem with W + e D and
// u - b - e D p_k (D = diag(W), e = kProximalWeight, p_k the impulses so far), which is well posed, and whose fixed
// point is the problem itself. A solve that has not met the accuracy when its iterations run out keeps its last
// iterate.
//
// Newton's step eliminates the unit rows of the Jacobian (sides apart: s_r = -F_r) and solves the rest by LU.
//
// The iteration runs in double. For another scalar (Jets, the reverse tape) one more Newton step in that scalar
// starts from the double solution: its value is the solution's (F is 0 there), its derivatives are the implicit
// function theorem's, dp = -J^-1 dF, exact for W, u, b and mu given as functions of the parameters.
#pragma once

#include <Eigen/Core>
#include <Eigen/LU>
#include <vector>

#include "tether/dynamics/scalars/scalar.h"

namespace tether {

inline constexpr double kImpulseRegularization = 1e-9;

template <typename T>
struct ImpulseBlock {
  Eigen::Index first_row = 0;
  int rows = 1;         // the gap row, then the slip rows (none without friction or for a limit)
  T friction = T(0.0);  // mu
};

// The iteration in double behind every scalar's solve (compiled once, not once per scalar).
class CoulombIteration {
 public:
  struct Block {
    Eigen::Index first_row = 0;
    int rows = 1;
    double friction = 0.0;
  };

  // The problem's W, u - b and blocks, to be filled before Iterate.
  Eigen::MatrixXd& delassus() { return delassus_; }
  Eigen::VectorXd& shift() { return shift_; }
  std::vector<Block>& blocks() { return blocks_; }

  // |S F|_inf asked for (a rate), and accepted where the problem turns out degenerate (the header), or is taken to
  // be so from the start
  struct Accuracy {
    double goal = 0.0, acceptable = 0.0;
    bool degenerate = false;
  };
  // Newton's steps on the problem, then proximal steps where they did not converge, from *impulses, which receives
  // the last iterate; |S F|_inf there.
  double Iterate(const Accuracy& accuracy, Eigen::VectorXd* impulses);
  // The LU factors of F's Jacobian at p as the steps on the problem take it (W + eps diag(W)), and the scalings rho
  const Eigen::PartialPivLU<Eigen::MatrixXd>& FactorJacobian(const Eigen::VectorXd& impulses);
  const std::vector<double>& rho_normal() const { return rho_normal_; }
  const std::vector<double>& rho_tangent() const { return rho_tangent_; }

  int newton_iterations() const { return newton_iterations_; }
  int sweeps() const { return sweeps_; }
  bool degenerate() const { return degenerate_; }  // whether the last Iterate found its problem degenerate
  // the accuracy the last Iterate was held to: the goal, or the acceptable one where its problem was degenerate
  double Asked(const Accuracy& accuracy) const { return degenerate_ ? accuracy.acceptable : accuracy.goal; }

 private:
  // |S F(p)|_inf into largest and |S F(p)|^2 of the problem with W = w and u - b = shift, F into residual_
  double Merit(const Eigen::MatrixXd& w, const Eigen::VectorXd& shift, const Eigen::VectorXd& impulses,
               double* largest);
  // one projected Gauss-Seidel sweep
  void Sweep(const Eigen::MatrixXd& w, const Eigen::VectorXd& shift, Eigen::VectorXd* impulses) const;
  // At most `iterations` Newton steps on that problem, their Jacobians from w_steps, or where the line search
  // refuses such a step and `fall_back`, from W + 1e-3 diag(W) (stepping_); |S F|_inf after them.
  double Newton(const Eigen::MatrixXd& w, const Eigen::VectorXd& shift, const Eigen::MatrixXd& w_steps, bool fall_back,
                int iterations, const Accuracy& accuracy, Eigen::VectorXd* impulses);

  Eigen::MatrixXd delassus_, regularized_, proximal_, stepping_;  // W, and W + eps diag(W) for three eps (.cc)
  bool stepping_ready_ = false;  // whether stepping_ is this Iterate's (it is made where a step needs it)
  Eigen::VectorXd shift_, proximal_shift_;             // u - b, and the proximal step's
  std::vector<Block> blocks_;
  std::vector<double> friction_, rho_normal_, rho_tangent_;
  // Newton's step from jacobian_ and residual_ into step_, the unit rows (unit_) eliminated
  void ReducedStep();

  Eigen::VectorXd rates_, residual_, step_, trial_, reduced_rhs_;  // rates_: y = u - b + W p
  Eigen::MatrixXd jacobian_, reduced_;
  std::vector<char> unit_;
  std::vector<Eigen::Index> kept_;
  Eigen::PartialPivLU<Eigen::MatrixXd> lu_;
  int newton_iterations_ = 0, sweeps_ = 0;
  bool degenerate_ = false;
};

template <typename T>
class CoulombImpulses {
 public:
  using Matrix = Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>;

  // Solves the problem above from `impulses` (a start: the last step's, or 0), writing the solution there. True
  // when every row's |F| / rho is at most `tolerance` (a rate), or `acceptable` where the problem is degenerate;
  // false, with the last iterate (within the cones), when the iterations ran out. `degenerate`, where given, says
  // whether the problem is taken as degenerate from the start, and receives whether it was.
  bool Solve(const Matrix& delassus, const VecX<T>& rates, const VecX<T>& targets,
             const std::vector<ImpulseBlock<T>>& blocks, double tolerance, VecX<T>* impulses, double acceptable = 0.0,
             bool* degenerate = nullptr);

  int newton_iterations() const { return iteration_.newton_iterations(); }  // of the last Solve
  int sweeps() const { return iteration_.sweeps(); }

 private:
  CoulombIteration iteration_;
  Eigen::VectorXd values_;
};

}  // namespace tether
