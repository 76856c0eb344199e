// Coulomb's impulse problem by Newton's method on Alart and Curnier's function (coulomb_impulses.h states the maths).
#include "tether/dynamics/solvers/coulomb_impulses.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <type_traits>

namespace tether {
namespace {

constexpr int kMostExactIterations = 8;    // on the problem itself, before proximal steps
// the steps' Jacobian's W + eps diag(W): bounded steps along W's null space (redundant rows), which the line search
// would otherwise refuse
constexpr double kStepRegularization = 1e-3;
constexpr int kMostNewtonIterations = 10;  // on each proximal step's problem
constexpr int kMostProximalSteps = 4;
constexpr double kProximalWeight = 1e-5;  // eps of the proximal steps, relative to W's diagonal
constexpr int kMostBacktracks = 12;       // step lengths 1, 1/2, ..., 1/2^11
constexpr double kArmijo = 1e-4;          // the decrease of |S F|^2 a step must give, against its linear prediction
constexpr int kSweepsPerRestart = 10;     // Gauss-Seidel sweeps where Newton's step does not decrease |S F|^2

// F of Alart and Curnier's function at p (the header), given y = shift + W p, and where `jacobian` is not null the
// element of its generalized Jacobian that Newton's method uses, in double (w_values: W's values): a row of rho W
// where F is rho y (pushing, sticking), a unit row where F is p (apart), the projection's derivative where a side
// slides.
template <typename S, typename Block>
void AlartCurnier(const VecX<S>& y, const std::vector<Block>& blocks, const std::vector<S>& friction,
                  const std::vector<double>& rho_normal, const std::vector<double>& rho_tangent, const VecX<S>& p,
                  VecX<S>* f, const Eigen::MatrixXd& w_values, Eigen::MatrixXd* jacobian,
                  std::vector<char>* unit = nullptr) {
  using std::sqrt;
  f->resize(p.size());
  if (jacobian != nullptr) jacobian->setZero(p.size(), p.size());
  if (unit != nullptr) unit->assign(p.size(), 0);
  auto unit_row = [&](Eigen::Index r) {
    (*f)[r] = p[r];
    if (jacobian != nullptr) (*jacobian)(r, r) = 1.0;
    if (unit != nullptr) (*unit)[r] = 1;
  };
  for (size_t b = 0; b < blocks.size(); ++b) {
    const Eigen::Index n = blocks[b].first_row;
    const int tangents = std::min(blocks[b].rows - 1, 2);  // a 3D contact has two
    if (!(rho_normal[b] > 0.0)) {  // a block that no impulse moves (its bodies held by the equality rows)
      for (int r = 0; r <= tangents; ++r) unit_row(n + r);
      continue;
    }
    const S a = p[n] - rho_normal[b] * y[n];
    const bool pushing = Value(a) > 0.0;
    if (pushing) {
      (*f)[n] = rho_normal[b] * y[n];
      if (jacobian != nullptr) jacobian->row(n) = rho_normal[b] * w_values.col(n).transpose();  // W is symmetric
    } else {
      unit_row(n);
    }
    if (tangents == 0) continue;
    const double rho = rho_tangent[b];
    const S radius = pushing ? S(friction[b] * a) : S(0.0);
    S z[2];
    double length = 0.0;
    for (int t = 0; t < tangents; ++t) {
      z[t] = p[n + 1 + t] - rho * y[n + 1 + t];
      length += Value(z[t]) * Value(z[t]);
    }
    length = std::sqrt(length);
    if (!(rho > 0.0) || !(Value(radius) > 0.0)) {  // no friction impulse: apart, or rows no impulse moves
      for (int t = 0; t < tangents; ++t) unit_row(n + 1 + t);
    } else if (length <= Value(radius)) {  // sticking
      for (int t = 0; t < tangents; ++t) {
        (*f)[n + 1 + t] = rho * y[n + 1 + t];
        if (jacobian != nullptr) jacobian->row(n + 1 + t) = rho * w_values.col(n + 1 + t).transpose();
      }
    } else {  // sliding: F_t = p_t - R z / |z|
      S norm_squared = S(0.0);
      for (int t = 0; t < tangents; ++t) norm_squared += z[t] * z[t];
      const S scale = radius / sqrt(norm_squared);
      for (int t = 0; t < tangents; ++t) (*f)[n + 1 + t] = p[n + 1 + t] - scale * z[t];
      if (jacobian == nullptr) continue;
      // dP = (R / |z|) (I - zh zh^T) dz + zh dR,  dz = E_t - rho W_t,  dR = mu (e_n - rho_n W_n)
      const double s = Value(scale), mu = Value(friction[b]);
      double unit[2];
      for (int t = 0; t < tangents; ++t) unit[t] = Value(z[t]) / length;
      for (int t = 0; t < tangents; ++t) {
        auto row = jacobian->row(n + 1 + t);
        row[n + 1 + t] = 1.0;
        for (int k = 0; k < tangents; ++k) {
          const double projector = s * ((t == k ? 1.0 : 0.0) - unit[t] * unit[k]);
          row[n + 1 + k] -= projector;
          for (Eigen::Index c = 0; c < row.size(); ++c) row[c] += projector * rho * w_values(c, n + 1 + k);
        }
        row[n] -= unit[t] * mu;
        for (Eigen::Index c = 0; c < row.size(); ++c) row[c] += unit[t] * mu * rho_normal[b] * w_values(c, n);
      }
    }
  }
}

Eigen::VectorXd Values(const VecX<double>& x) { return x; }
template <typename T>
Eigen::VectorXd Values(const VecX<T>& x) {
  Eigen::VectorXd values(x.size());
  for (Eigen::Index i = 0; i < x.size(); ++i) values[i] = Value(x[i]);
  return values;
}

}  // namespace

double CoulombIteration::Iterate(const Accuracy& accuracy, Eigen::VectorXd* impulses) {
  regularized_ = delassus_;
  regularized_.diagonal() *= 1.0 + kImpulseRegularization;
  stepping_ready_ = false;
  friction_.clear();
  rho_normal_.clear();
  rho_tangent_.clear();
  for (const Block& block : blocks_) {
    friction_.push_back(block.friction);
    const double w_nn = regularized_(block.first_row, block.first_row);
    double w_tt = 0.0;
    for (int t = 1; t < block.rows; ++t) w_tt = std::max(w_tt, regularized_(block.first_row + t, block.first_row + t));
    rho_normal_.push_back(w_nn > 0.0 ? 1.0 / w_nn : 0.0);
    rho_tangent_.push_back(w_tt > 0.0 ? 1.0 / w_tt : 0.0);
  }
  Eigen::VectorXd& p = *impulses;
  newton_iterations_ = sweeps_ = 0;
  // proximal steps: each solves the problem with W + eps D and u - b - eps D p_k (the last step's impulses p_k),
  // well posed where W is singular, and at its fixed point the problem itself
  double largest = Newton(delassus_, shift_, regularized_, true, kMostExactIterations, accuracy, &p);
  if (largest > Asked(accuracy)) {
    proximal_ = delassus_;
    proximal_.diagonal() *= 1.0 + kProximalWeight;
  }
  for (int step = 0; largest > Asked(accuracy) && step < kMostProximalSteps; ++step) {
    proximal_shift_ = shift_ - kProximalWeight * (delassus_.diagonal().asDiagonal() * p);
    Newton(proximal_, proximal_shift_, proximal_, false, kMostNewtonIterations, accuracy, &p);
    Merit(delassus_, shift_, p, &largest);
  }
  return largest;
}

const Eigen::PartialPivLU<Eigen::MatrixXd>& CoulombIteration::FactorJacobian(const Eigen::VectorXd& impulses) {
  rates_.noalias() = delassus_ * impulses;
  rates_ += shift_;
  AlartCurnier(rates_, blocks_, friction_, rho_normal_, rho_tangent_, impulses, &residual_, regularized_, &jacobian_);
  lu_.compute(jacobian_);
  return lu_;
}

double CoulombIteration::Merit(const Eigen::MatrixXd& w, const Eigen::VectorXd& shift, const Eigen::VectorXd& impulses,
                               double* largest) {
  rates_.noalias() = w * impulses;
  rates_ += shift;
  AlartCurnier(rates_, blocks_, friction_, rho_normal_, rho_tangent_, impulses, &residual_, w, nullptr);
  double sum = 0.0;
  *largest = 0.0;
  for (size_t b = 0; b < blocks_.size(); ++b) {
    for (int r = 0; r < blocks_[b].rows; ++r) {
      const double rho = r == 0 ? rho_normal_[b] : rho_tangent_[b];
      const double rate = rho > 0.0 ? residual_[blocks_[b].first_row + r] / rho : residual_[blocks_[b].first_row + r];
      sum += rate * rate;
      *largest = std::max(*largest, std::abs(rate));
    }
  }
  return sum;
}

// The gap row's impulse p_n <- max(0, p_n - y_n / W_nn), then the slip rows' p_t <- P(p_t - y_t / max W_tt, mu p_n)
void CoulombIteration::Sweep(const Eigen::MatrixXd& w, const Eigen::VectorXd& shift, Eigen::VectorXd* impulses) const {
  Eigen::VectorXd& p = *impulses;
  for (size_t b = 0; b < blocks_.size(); ++b) {
    const Eigen::Index n = blocks_[b].first_row;
    if (!(rho_normal_[b] > 0.0)) continue;
    p[n] = std::max(0.0, p[n] - rho_normal_[b] * (shift[n] + w.row(n).dot(p)));
    if (blocks_[b].rows == 1 || !(rho_tangent_[b] > 0.0)) continue;
    double slip[2] = {0.0, 0.0}, length = 0.0;
    for (int t = 1; t < blocks_[b].rows; ++t) {
      slip[t - 1] = p[n + t] - rho_tangent_[b] * (shift[n + t] + w.row(n + t).dot(p));
      length += slip[t - 1] * slip[t - 1];
    }
    length = std::sqrt(length);
    const double radius = friction_[b] * p[n], scale = length > radius ? radius / length : 1.0;
    for (int t = 1; t < blocks_[b].rows; ++t) p[n + t] = scale * slip[t - 1];
  }
}

double CoulombIteration::Newton(const Eigen::MatrixXd& w, const Eigen::VectorXd& shift, const Eigen::MatrixXd& w_steps,
                                bool fall_back, int iterations, const Accuracy& accuracy, Eigen::VectorXd* impulses) {
  Eigen::VectorXd& p = *impulses;
  double largest = 0.0, merit = Merit(w, shift, p, &largest), goal = accuracy.goal;
  // one step with jacobian_w in the Jacobian, shortened until |S F|^2 decreases enough; false where none does
  const auto step = [&](const Eigen::MatrixXd& jacobian_w) {
    rates_.noalias() = w * p;
    rates_ += shift;
    AlartCurnier(rates_, blocks_, friction_, rho_normal_, rho_tangent_, p, &residual_, jacobian_w, &jacobian_, &unit_);
    ReducedStep();
    double length = 1.0;
    for (int backtrack = 0; step_.allFinite() && backtrack < kMostBacktracks; ++backtrack, length /= 2) {
      trial_ = p + length * step_;
      double trial_largest = 0.0;
      const double trial_merit = Merit(w, shift, trial_, &trial_largest);
      if (trial_merit <= (1.0 - 2.0 * kArmijo * length) * merit) {
        p.swap(trial_);
        merit = trial_merit;
        largest = trial_largest;
        return true;
      }
    }
    return false;
  };
  bool degenerate = accuracy.degenerate;
  for (int iteration = 0; largest > goal && iteration < iterations; ++iteration) {
    ++newton_iterations_;
    if (!degenerate && step(w_steps)) continue;
    // a step along W's null space that the line search refused (redundant rows): the problem is degenerate, its
    // solution no longer converges quadratically, and the accuracy accepted is the coarser one
    degenerate = true;
    goal = std::max(goal, accuracy.acceptable);
    if (fall_back && !stepping_ready_) {  // made the first time a step of this Iterate needs it
      stepping_ = delassus_;
      stepping_.diagonal() *= 1.0 + kStepRegularization;
      stepping_ready_ = true;
    }
    if (fall_back && step(stepping_)) continue;
    for (int sweep = 0; sweep < kSweepsPerRestart; ++sweep) Sweep(w, shift, &p);
    sweeps_ += kSweepsPerRestart;
    merit = Merit(w, shift, p, &largest);
  }
  if (fall_back) degenerate_ = degenerate;
  return largest;
}

// Newton's step J s = -F, where a unit row of J (a side apart, its impulse driven to 0) gives s_r = -F_r at once:
// the others solve J_RR s_R = -F_R - J_RU s_U.
void CoulombIteration::ReducedStep() {
  const Eigen::Index n = residual_.size();
  kept_.clear();
  step_.resize(n);
  for (Eigen::Index r = 0; r < n; ++r) {
    if (unit_[r]) {
      step_[r] = -residual_[r];
    } else {
      kept_.push_back(r);
    }
  }
  const Eigen::Index m = static_cast<Eigen::Index>(kept_.size());
  if (m == 0) return;
  reduced_.resize(m, m);
  reduced_rhs_.resize(m);
  for (Eigen::Index i = 0; i < m; ++i) {
    const Eigen::Index r = kept_[i];
    double rhs = -residual_[r];
    for (Eigen::Index c = 0; c < n; ++c) {
      if (unit_[c]) rhs -= jacobian_(r, c) * step_[c];
    }
    reduced_rhs_[i] = rhs;
    for (Eigen::Index j = 0; j < m; ++j) reduced_(i, j) = jacobian_(r, kept_[j]);
  }
  lu_.compute(reduced_);
  reduced_rhs_ = lu_.solve(reduced_rhs_);
  for (Eigen::Index i = 0; i < m; ++i) step_[kept_[i]] = reduced_rhs_[i];
}

template <typename T>
bool CoulombImpulses<T>::Solve(const Matrix& delassus, const VecX<T>& rates, const VecX<T>& targets,
                               const std::vector<ImpulseBlock<T>>& blocks, double tolerance, VecX<T>* impulses,
                               double acceptable, bool* degenerate) {
  const Eigen::Index n = rates.size();
  Eigen::MatrixXd& w = iteration_.delassus();
  w.resize(n, n);
  for (Eigen::Index c = 0; c < n; ++c) {
    for (Eigen::Index r = 0; r < n; ++r) w(r, c) = Value(delassus(r, c));
  }
  iteration_.shift() = Values(VecX<T>(rates - targets));
  iteration_.blocks().clear();
  for (const ImpulseBlock<T>& block : blocks) {
    iteration_.blocks().push_back({block.first_row, block.rows, Value(block.friction)});
  }
  values_ = Values(*impulses);
  const CoulombIteration::Accuracy accuracy{tolerance, std::max(tolerance, acceptable),
                                            degenerate != nullptr && *degenerate};
  const double largest = iteration_.Iterate(accuracy, &values_);
  if (degenerate != nullptr) *degenerate = iteration_.degenerate();
  if constexpr (std::is_same_v<T, double>) {
    *impulses = values_;
  } else {
    // one Newton step in T from the solution: the value stays, the derivatives become the implicit function's
    std::vector<T> friction;
    for (const ImpulseBlock<T>& block : blocks) friction.push_back(block.friction);
    const VecX<T> start = values_.cast<T>();
    VecX<T> f;
    const VecX<T> y = rates - targets + delassus * start;
    AlartCurnier(y, blocks, friction, iteration_.rho_normal(), iteration_.rho_tangent(), start, &f, w, nullptr);
    const Eigen::PartialPivLU<Eigen::MatrixXd>& lu = iteration_.FactorJacobian(values_);
    // start - J^-1 f with the double factors P J = L U applied to the scalar's vector
    const Eigen::MatrixXd& factors = lu.matrixLU();
    VecX<T> x = lu.permutationP() * f;
    for (Eigen::Index i = 0; i < n; ++i) {
      for (Eigen::Index j = 0; j < i; ++j) x[i] -= factors(i, j) * x[j];
    }
    for (Eigen::Index i = n - 1; i >= 0; --i) {
      for (Eigen::Index j = i + 1; j < n; ++j) x[i] -= factors(i, j) * x[j];
      x[i] /= factors(i, i);
    }
    *impulses = start - x;
  }
  return largest <= iteration_.Asked(accuracy);
}

#define TETHER_INSTANTIATE_COULOMB_IMPULSES(T) template class CoulombImpulses<T>;
TETHER_FOR_EACH_SCALAR(TETHER_INSTANTIATE_COULOMB_IMPULSES)

}  // namespace tether
