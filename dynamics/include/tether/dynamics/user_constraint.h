// User-defined constraints: write the residual C(q_A, q_B) once, as a template on its scalar, and tether
// derives the Jacobian J = dC/d(q_A, q_B) and the term Jdot q' = q'^T (d^2 C/dq^2) q' with dual numbers
// (dual.h), for double and for Jet scalars alike.
//
// A residual is a functor
//   struct Residual {
//     static constexpr int kRows = ...;                               // number of scalar equations
//     template <typename S> void operator()(const S* q_a, const S* q_b, S* c) const;
//   };
// where q_a holds body A's coordinates (a particle: its d position coordinates; a planar rigid body:
// x, y, angle; the world: nothing, the pointer must not be read). Use `using std::sqrt;` etc. inside, write
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

#include "tether/dynamics/constraint_rows.h"
#include "tether/dynamics/dual.h"

namespace tether {

// Largest number of coordinates of one body (a planar rigid body or a 3D particle).
inline constexpr int kMaxBodyCoordinates = 3;
// Largest number of rows of one user constraint (the step keeps them on the stack).
inline constexpr int kMaxUserRows = 8;

template <typename T>
struct BodyState {
  const T* q = nullptr;  // the body's coordinates (nullptr for the world)
  const T* v = nullptr;  // and velocities
  int size = 0;          // how many (0 for the world)
};

// One row of a user constraint: value, bias = Jdot q', and the gradient over (q_A, q_B) concatenated.
template <typename T>
struct UserRow {
  T value = T(0.0);
  T bias = T(0.0);
  T gradient[2 * kMaxBodyCoordinates];
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

 private:
  static constexpr int kRows = Residual::kRows;
  static_assert(kRows >= 1 && kRows <= kMaxUserRows, "a user constraint has 1 to kMaxUserRows rows");

  // Evaluates the residual at q + eps * direction (q and direction over (q_A, q_B) concatenated).
  template <typename S, typename T>
  void Seeded(const BodyState<T>& a, const BodyState<T>& b, const T* direction, S* c) const {
    S x[2 * kMaxBodyCoordinates];
    const int n = a.size + b.size;
    for (int k = 0; k < n; ++k) {
      const T& value = k < a.size ? a.q[k] : b.q[k - a.size];
      x[k] = S(value, direction[k]);
    }
    residual_(x, x + a.size, c);
  }

  template <typename T>
  void EvaluateWith(const BodyState<T>& a, const BodyState<T>& b, bool velocity_terms, UserRow<T>* rows) const {
    const int n = a.size + b.size;
    Dual<T> c[kRows];
    T unit[2 * kMaxBodyCoordinates];
    for (int j = 0; j < n; ++j) {
      for (int k = 0; k < n; ++k) unit[k] = T(k == j ? 1.0 : 0.0);
      Seeded<Dual<T>>(a, b, unit, c);
      for (int i = 0; i < kRows; ++i) {
        rows[i].value = c[i].v;
        rows[i].gradient[j] = c[i].d;
      }
    }
    if (!velocity_terms) return;
    // q'^T H q' from C(q + eps1 q' + eps2 q'): seed both levels with the velocity.
    using D2 = Dual<Dual<T>>;
    D2 x[2 * kMaxBodyCoordinates];
    for (int k = 0; k < n; ++k) {
      const T& q = k < a.size ? a.q[k] : b.q[k - a.size];
      const T& v = k < a.size ? a.v[k] : b.v[k - a.size];
      x[k] = D2(Dual<T>(q, v), Dual<T>(v, T(0.0)));
    }
    D2 c2[kRows];
    residual_(x, x + a.size, c2);
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
