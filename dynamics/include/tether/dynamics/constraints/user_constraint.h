// User-defined constraints: write the residual C(q_A, q_B) once, as a template on its scalar, and tether
// derives the Jacobian with respect to the velocities, J = dC/dq N(q) (q' = N(q) v, configuration_space.h), and
// the term Jdot v = q'^T (d^2 C/dq^2) q' + dC/dq (N' v) with dual numbers (dual.h), for double and for Jet
// scalars alike: seeding q + eps1 q' + eps2 (q' + eps1 N' v) gives both at once.
//
// A residual is a functor
//   struct Residual {
//     static constexpr int kRows = ...;                               // number of scalar equations
//     template <typename S> void operator()(const S* q_a, const S* q_b, S* c) const;
//   };
// where q_a holds body A's coordinates (a particle: its d position coordinates; a planar rigid body:
// x, y, angle; a 3D rigid body: x, y, z, then its unit quaternion q_WB = (w, x, y, z); the world: nothing,
// the pointer must not be read). Use `using std::sqrt;` etc. inside, write
// constants as S(k), and keep to the functions dual.h lists. Example, a particle held on the circle
// x^2 + y^2 = r^2 (body A is the world):
//   struct OnCircle {
//     static constexpr int kRows = 1;
//     double radius;
//     template <typename S> void operator()(const S*, const S* q, S* c) const {
//       using std::sqrt;
//       c[0] = sqrt(q[0] * q[0] + q[1] * q[1]) - S(radius);
//     }
//   };
//   AddUserConstraint(&model, kWorld, bead, OnCircle{0.5});
#pragma once

#include <memory>

#include "tether/dynamics/constraints/constraint_rows.h"
#include "tether/dynamics/constraints/dual.h"
#include "tether/dynamics/model/configuration_space.h"

namespace tether {

// Largest number of coordinates and of velocities of one body (a 3D rigid body).
inline constexpr int kMaxBodyCoordinates = 7;
inline constexpr int kMaxBodyVelocities = 6;
// Largest number of rows of one user constraint (the step keeps them on the stack).
inline constexpr int kMaxUserRows = 8;

template <typename T>
struct BodyState {
  const T* q = nullptr;  // the body's coordinates (nullptr for the world)
  const T* v = nullptr;  // and velocities
  int q_size = 0;        // how many (0 for the world)
  int v_size = 0;
  BodyKind kind = BodyKind::kParticle;
  Vec4<double> principal_axes = Vec4<double>(1, 0, 0, 0);  // R_BP of a 3D rigid body
};

// One row of a user constraint: value, bias = Jdot v, and the gradient over (v_A, v_B) concatenated.
template <typename T>
struct UserRow {
  T value = T(0.0);
  T bias = T(0.0);
  T gradient[2 * kMaxBodyVelocities];
};

// The type-erased interface the simulator calls, once per scalar tether is compiled for.
class UserConstraint {
 public:
  virtual ~UserConstraint() = default;
  virtual int NumRows() const = 0;
  // Writes NumRows() rows; the bias only when velocity_terms is true.
  virtual void Evaluate(const BodyState<double>& a, const BodyState<double>& b, bool velocity_terms,
                        UserRow<double>* rows) const = 0;
  virtual void Evaluate(const BodyState<Jet>& a, const BodyState<Jet>& b, bool velocity_terms,
                        UserRow<Jet>* rows) const = 0;
  virtual void Evaluate(const BodyState<Rev>& a, const BodyState<Rev>& b, bool velocity_terms,
                        UserRow<Rev>* rows) const = 0;
};

template <class Residual>
class AutoDiffUserConstraint final : public UserConstraint {
 public:
  explicit AutoDiffUserConstraint(Residual residual) : residual_(std::move(residual)) {}
  int NumRows() const override { return Residual::kRows; }
  void Evaluate(const BodyState<double>& a, const BodyState<double>& b, bool velocity_terms,
                UserRow<double>* rows) const override {
    EvaluateWith(a, b, velocity_terms, rows);
  }
  void Evaluate(const BodyState<Jet>& a, const BodyState<Jet>& b, bool velocity_terms,
                UserRow<Jet>* rows) const override {
    EvaluateWith(a, b, velocity_terms, rows);
  }
  void Evaluate(const BodyState<Rev>& a, const BodyState<Rev>& b, bool velocity_terms,
                UserRow<Rev>* rows) const override {
    EvaluateWith(a, b, velocity_terms, rows);
  }

 private:
  static constexpr int kRows = Residual::kRows;
  static_assert(kRows >= 1 && kRows <= kMaxUserRows, "a user constraint has 1 to kMaxUserRows rows");

  // The residual at q + eps dq (dq over (q_A, q_B) concatenated), with S a dual number over T.
  template <typename S, typename T>
  void Seeded(const BodyState<T>& a, const BodyState<T>& b, const T* dq, S* c) const {
    S x[2 * kMaxBodyCoordinates];
    const int n = a.q_size + b.q_size;
    for (int k = 0; k < n; ++k) {
      const T& value = k < a.q_size ? a.q[k] : b.q[k - a.q_size];
      x[k] = S(value, dq[k]);
    }
    residual_(x, x + a.q_size, c);
  }

  // N(q) v and N' v (configuration_space.h) for both bodies, concatenated over (q_A, q_B).
  template <typename T>
  static void Rates(const BodyState<T>& a, const BodyState<T>& b, const T* v_a, const T* v_b, T* rate, T* second) {
    if (a.q_size) ConfigurationRate(a.kind, a.principal_axes, a.q_size, a.q, v_a, rate, second);
    if (b.q_size) ConfigurationRate(b.kind, b.principal_axes, b.q_size, b.q, v_b, rate + a.q_size, second + a.q_size);
  }

  template <typename T>
  void EvaluateWith(const BodyState<T>& a, const BodyState<T>& b, bool velocity_terms, UserRow<T>* rows) const {
    const int n = a.v_size + b.v_size;
    Dual<T> c[kRows];
    T unit[2 * kMaxBodyVelocities], dq[2 * kMaxBodyCoordinates], unused[2 * kMaxBodyCoordinates];
    for (int j = 0; j < n; ++j) {  // column j of J: the residual along the configuration direction N(q) e_j
      for (int k = 0; k < n; ++k) unit[k] = T(k == j ? 1.0 : 0.0);
      Rates(a, b, unit, unit + a.v_size, dq, unused);
      Seeded<Dual<T>>(a, b, dq, c);
      for (int i = 0; i < kRows; ++i) {
        rows[i].value = c[i].v;
        rows[i].gradient[j] = c[i].d;
      }
    }
    if (!velocity_terms) return;
    // q'^T H q' + dC/dq (N' v) from C(q + eps1 q' + eps2 (q' + eps1 N' v))
    T rate[2 * kMaxBodyCoordinates], second[2 * kMaxBodyCoordinates];
    Rates(a, b, a.v, b.v, rate, second);
    using D2 = Dual<Dual<T>>;
    D2 x[2 * kMaxBodyCoordinates];
    for (int k = 0; k < a.q_size + b.q_size; ++k) {
      const T& q = k < a.q_size ? a.q[k] : b.q[k - a.q_size];
      x[k] = D2(Dual<T>(q, rate[k]), Dual<T>(rate[k], second[k]));
    }
    D2 c2[kRows];
    residual_(x, x + a.q_size, c2);
    for (int i = 0; i < kRows; ++i) rows[i].bias = c2[i].d.d;
  }

  Residual residual_;
};

// Adds the constraint residual(q_A, q_B) = 0 between bodies a and b (either may be kWorld) to a model.
template <typename T, class Residual>
void AddUserConstraint(Model<T>* model, int body_a, int body_b, Residual residual) {
  model->user_constraints.push_back({model->NumConstraints(), body_a, body_b,
                                     std::make_shared<AutoDiffUserConstraint<Residual>>(std::move(residual))});
}

}  // namespace tether
