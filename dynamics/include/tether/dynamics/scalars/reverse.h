// Rev: a scalar for reverse-mode differentiation (the discrete adjoint, autodiff/adjoint.h), recording onto a
// Tape that covers a bounded piece of a run (one step, the initial state), never the whole run.
//
// A Rev is a value and the index of its node on the thread's active tape, or -1 for a constant. Every operation
// on a recorded operand pushes one node holding its parents and the partial derivatives,
//   y = f(x1, x2):   node y = {x1, df/dx1, x2, df/dx2},
// and Tape::Backward sweeps the nodes from the last down to a mark, adding  adjoint(x_k) += df/dx_k adjoint(y)
// (the chain rule in reverse: the cost of one gradient is a small multiple of the recorded evaluation, whatever
// the number of inputs). Operations on constants record nothing, so a run with no recorded inputs is a plain
// run in Rev arithmetic, value for value the run that a recorded replay repeats (the same code on the same
// numbers takes the same branches). An external operation (the Schur solve, schur_solver.h) records its outputs
// as nodes without parents and a function that maps their adjoints onto its inputs' when the sweep reaches them.
//
// Comparisons look at values only, as with Jets; Value(x) is the value.
#pragma once

#include <Eigen/Core>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <utility>
#include <vector>

namespace tether {

class Tape;

namespace internal {
inline thread_local Tape* active_tape = nullptr;
}  // namespace internal

// The active tape of this thread (nullptr when none): where recorded operations go.
inline Tape* ActiveTape() { return internal::active_tape; }

struct Rev {
  double a = 0.0;  // the value (named as Jet's)
  int index = -1;  // node on the active tape, -1 for a constant

  Rev() = default;
  explicit Rev(double value) : a(value) {}
  Rev(double value, int node) : a(value), index(node) {}

  Rev& operator+=(const Rev& y);
  Rev& operator-=(const Rev& y);
  Rev& operator*=(const Rev& y);
  Rev& operator/=(const Rev& y);
  Rev& operator+=(double y);
  Rev& operator-=(double y);
  Rev& operator*=(double y);
  Rev& operator/=(double y);

  // A node with one or two parents on the active tape.
  static int Record(int parent, double partial);
  static int Record(int parent0, double partial0, int parent1, double partial1);
};

class Tape {
 public:
  // Makes this tape the thread's active one until it is destroyed (tapes do not nest).
  Tape();
  ~Tape();
  Tape(const Tape&) = delete;
  Tape& operator=(const Tape&) = delete;

  // A recorded input.
  Rev Variable(double value);
  int size() const { return size_; }
  // What the nodes and their adjoints hold (their buffers' capacity, which only grows).
  std::int64_t Bytes() const {
    return static_cast<std::int64_t>(nodes_.capacity() * sizeof(Node) + adjoints_.capacity() * sizeof(double));
  }

  // An external operation: `count` outputs recorded as nodes without parents, and `backward`, called with their
  // adjoints once every later node has been swept, which must add to its inputs' adjoints (AddAdjoint).
  using ExternalBackward = std::function<void(const double* output_adjoints, Tape* tape)>;
  int RecordExternal(int count, ExternalBackward backward);

  double Adjoint(const Rev& x) const {
    return x.index < 0 || x.index >= static_cast<int>(adjoints_.size()) ? 0.0 : adjoints_[x.index];
  }
  void AddAdjoint(const Rev& x, double value) { AddAdjoint(x.index, value); }
  void AddAdjoint(int node, double value) {
    if (node < 0) return;
    if (node >= static_cast<int>(adjoints_.size())) adjoints_.resize(size_, 0.0);
    adjoints_[node] += value;
  }
  // A record of type Record for an external operation (default-constructed the first time): one that no recorded
  // operation holds any more (swept or dropped), so that its buffers serve again instead of being allocated per
  // evaluation. The tape keeps them until it is destroyed.
  template <typename Record>
  std::shared_ptr<Record> Reusable() {
    static const size_t kind = next_record_kind_++;
    if (kind >= pools_.size()) pools_.resize(kind + 1);
    std::vector<std::shared_ptr<void>>& pool = pools_[kind];
    for (const std::shared_ptr<void>& record : pool) {
      if (record.use_count() == 1) return std::static_pointer_cast<Record>(record);
    }
    return std::static_pointer_cast<Record>(pool.emplace_back(std::make_shared<Record>()));
  }

  // Sweeps nodes [mark, size) in reverse: the nodes below the mark keep what the sweep added to their adjoints,
  // so that a prefix (the initial state), swept last, collects over many pieces (the steps).
  void Backward(int mark);
  // Drops the nodes [mark, size).
  void Rewind(int mark);

 private:
  friend struct Rev;
  struct Node {
    int parent[2];
    double partial[2];
  };
  struct External {
    int first, count;
    ExternalBackward backward;
  };
  // Inlined into every recorded operation, with the buffer's growth out of line (Grow, reverse.cc): a push_back
  // there put its reallocation into every operation of every function instantiated for Rev, which made those
  // instantiations most of the library's compile time (the constraint rows' Rev part 110 s at -O3; 36 s so).
  int Push(int p0, double d0, int p1, double d1) {
    if (__builtin_expect(size_ == static_cast<int>(nodes_.size()), 0)) Grow(1);
    nodes_[size_] = {{p0, p1}, {d0, d1}};
    return size_++;
  }
  // Room for `count` more nodes: the buffer at least doubled.
  void Grow(int count);

 public:
  static constexpr int kBytesPerNode = sizeof(Node) + sizeof(double);  // a node and its adjoint

 private:
  // The nodes and adjoints, in buffers a thread's tapes pass on to the next one (Tape(), ~Tape()): a gradient's
  // record is the same size every time, and a fresh buffer would be paged in again by the kernel on every call.
  std::vector<Node> nodes_;  // the nodes [0, size_); the rest is room (its size only grows)
  int size_ = 0;
  std::vector<double> adjoints_;                           // of the nodes [0, adjoints_.size()); the others' are zero
  std::vector<External> externals_;                        // in the order recorded
  std::vector<std::vector<std::shared_ptr<void>>> pools_;  // Reusable's records, by the record type's number
  inline static std::atomic<size_t> next_record_kind_{0};  // numbers the record types Reusable has seen
  inline static thread_local std::vector<Node> spare_nodes_;  // the buffers of this thread's last tape
  inline static thread_local std::vector<double> spare_adjoints_;
  Tape* previous_ = nullptr;
};

__attribute__((always_inline)) inline int Rev::Record(int parent, double partial) {
  return ActiveTape()->Push(parent, partial, -1, 0.0);
}
// A constant parent is dropped (the other one first): one push, its operands chosen without branches.
__attribute__((always_inline)) inline int Rev::Record(int parent0, double partial0, int parent1, double partial1) {
  const bool first = parent0 >= 0, second = parent1 >= 0;
  return ActiveTape()->Push(first ? parent0 : parent1, first ? partial0 : partial1, first && second ? parent1 : -1,
                            first && second ? partial1 : 0.0);
}

inline double Value(const Rev& x) { return x.a; }

// y = f(x) with f(x) = value and f'(x) = partial (partial evaluated only when x is recorded)
template <typename Partial>
__attribute__((always_inline)) inline Rev Unary(const Rev& x, double value, Partial partial) {
  if (__builtin_expect(x.index < 0, 1)) return Rev(value);
  return Rev(value, Rev::Record(x.index, partial()));
}
template <typename Partials>
__attribute__((always_inline)) inline Rev Binary(const Rev& x, const Rev& y, double value, Partials partials) {
  if (__builtin_expect((x.index & y.index) < 0, 1)) {  // both constants: both sign bits set
    return Rev(value);
  }
  const auto [dx, dy] = partials();
  return Rev(value, Rev::Record(x.index, dx, y.index, dy));
}

inline Rev operator+(const Rev& x) { return x; }
inline Rev operator-(const Rev& x) {
  return Unary(x, -x.a, [] { return -1.0; });
}
// x + c and x - c for a constant c take x's node: their derivative is x's, so their adjoint may be added to x's
// directly (a node saved, e.g. for every point offset added to a particle's position).
inline Rev operator+(const Rev& x, const Rev& y) {
  if (y.index < 0) return Rev(x.a + y.a, x.index);
  if (x.index < 0) return Rev(x.a + y.a, y.index);
  return Rev(x.a + y.a, Rev::Record(x.index, 1.0, y.index, 1.0));
}
inline Rev operator-(const Rev& x, const Rev& y) {
  if (y.index < 0) return Rev(x.a - y.a, x.index);
  return Binary(x, y, x.a - y.a, [] { return std::pair{1.0, -1.0}; });
}
inline Rev operator*(const Rev& x, const Rev& y) {
  return Binary(x, y, x.a * y.a, [&] { return std::pair{y.a, x.a}; });
}
inline Rev operator/(const Rev& x, const Rev& y) {
  const double q = x.a / y.a;
  return Binary(x, y, q, [&] { return std::pair{1.0 / y.a, -q / y.a}; });
}
inline Rev operator+(const Rev& x, double y) { return Rev(x.a + y, x.index); }
inline Rev operator+(double x, const Rev& y) { return y + x; }
inline Rev operator-(const Rev& x, double y) { return Rev(x.a - y, x.index); }
inline Rev operator-(double x, const Rev& y) {
  return Unary(y, x - y.a, [] { return -1.0; });
}
inline Rev operator*(const Rev& x, double y) {
  return Unary(x, x.a * y, [y] { return y; });
}
inline Rev operator*(double x, const Rev& y) { return y * x; }
inline Rev operator/(const Rev& x, double y) {
  return Unary(x, x.a / y, [y] { return 1.0 / y; });
}
inline Rev operator/(double x, const Rev& y) {
  const double q = x / y.a;
  return Unary(y, q, [&] { return -q / y.a; });
}

inline Rev& Rev::operator+=(const Rev& y) { return *this = *this + y; }
inline Rev& Rev::operator-=(const Rev& y) { return *this = *this - y; }
inline Rev& Rev::operator*=(const Rev& y) { return *this = *this * y; }
inline Rev& Rev::operator/=(const Rev& y) { return *this = *this / y; }
inline Rev& Rev::operator+=(double y) { return *this = *this + y; }
inline Rev& Rev::operator-=(double y) { return *this = *this - y; }
inline Rev& Rev::operator*=(double y) { return *this = *this * y; }
inline Rev& Rev::operator/=(double y) { return *this = *this / y; }

#define TETHER_REV_COMPARISON(op)                                            \
  inline bool operator op(const Rev& x, const Rev& y) { return x.a op y.a; } \
  inline bool operator op(const Rev& x, double y) { return x.a op y; }       \
  inline bool operator op(double x, const Rev& y) { return x op y.a; }
TETHER_REV_COMPARISON(<)
TETHER_REV_COMPARISON(<=)
TETHER_REV_COMPARISON(>)
TETHER_REV_COMPARISON(>=)
TETHER_REV_COMPARISON(==)
TETHER_REV_COMPARISON(!=)
#undef TETHER_REV_COMPARISON

inline Rev sqrt(const Rev& x) {
  const double s = std::sqrt(x.a);
  return Unary(x, s, [s] { return 0.5 / s; });
}
inline Rev sin(const Rev& x) {
  return Unary(x, std::sin(x.a), [&] { return std::cos(x.a); });
}
inline Rev cos(const Rev& x) {
  return Unary(x, std::cos(x.a), [&] { return -std::sin(x.a); });
}
inline Rev tan(const Rev& x) {
  const double t = std::tan(x.a);
  return Unary(x, t, [t] { return 1.0 + t * t; });
}
inline Rev asin(const Rev& x) {
  return Unary(x, std::asin(x.a), [&] { return 1.0 / std::sqrt(1.0 - x.a * x.a); });
}
inline Rev acos(const Rev& x) {
  return Unary(x, std::acos(x.a), [&] { return -1.0 / std::sqrt(1.0 - x.a * x.a); });
}
inline Rev atan(const Rev& x) {
  return Unary(x, std::atan(x.a), [&] { return 1.0 / (1.0 + x.a * x.a); });
}
inline Rev exp(const Rev& x) {
  const double e = std::exp(x.a);
  return Unary(x, e, [e] { return e; });
}
inline Rev log(const Rev& x) {
  return Unary(x, std::log(x.a), [&] { return 1.0 / x.a; });
}
inline Rev log1p(const Rev& x) {
  return Unary(x, std::log1p(x.a), [&] { return 1.0 / (1.0 + x.a); });
}
inline Rev tanh(const Rev& x) {
  const double t = std::tanh(x.a);
  return Unary(x, t, [t] { return 1.0 - t * t; });
}
inline Rev abs(const Rev& x) {
  return Unary(x, std::abs(x.a), [&] { return x.a < 0.0 ? -1.0 : 1.0; });
}
inline Rev fabs(const Rev& x) { return abs(x); }
// atan2(y, x): d/dy = x / r^2, d/dx = -y / r^2
inline Rev atan2(const Rev& y, const Rev& x) {
  return Binary(y, x, std::atan2(y.a, x.a), [&] {
    const double r2 = x.a * x.a + y.a * y.a;
    return std::pair{x.a / r2, -y.a / r2};
  });
}
inline Rev hypot(const Rev& x, const Rev& y) {
  const double r = std::hypot(x.a, y.a);
  return Binary(x, y, r, [&] { return std::pair{x.a / r, y.a / r}; });
}
inline Rev pow(const Rev& x, double p) {
  const double value = std::pow(x.a, p);
  return Unary(x, value, [&] { return p * std::pow(x.a, p - 1.0); });
}
inline Rev pow(const Rev& x, const Rev& p) {
  const double value = std::pow(x.a, p.a);
  return Binary(x, p, value, [&] {
    return std::pair{p.a * std::pow(x.a, p.a - 1.0), x.a > 0.0 ? value * std::log(x.a) : 0.0};
  });
}
inline Rev pow(double x, const Rev& p) { return pow(Rev(x), p); }
inline bool isfinite(const Rev& x) { return std::isfinite(x.a); }
inline bool isnan(const Rev& x) { return std::isnan(x.a); }

}  // namespace tether

namespace Eigen {

template <>
struct NumTraits<tether::Rev> {
  using Real = tether::Rev;
  using NonInteger = tether::Rev;
  using Nested = tether::Rev;
  using Literal = tether::Rev;
  static Real dummy_precision() { return Real(1e-12); }
  static Real epsilon() { return Real(std::numeric_limits<double>::epsilon()); }
  static int digits10() { return NumTraits<double>::digits10(); }
  enum {
    IsComplex = 0,
    IsInteger = 0,
    IsSigned = 1,
    ReadCost = 1,
    AddCost = 2,
    MulCost = 3,
    HasFloatingPoint = 1,
    RequireInitialization = 1
  };
  static Real highest() { return Real(std::numeric_limits<double>::max()); }
  static Real lowest() { return Real(-std::numeric_limits<double>::max()); }
};

template <typename BinaryOp>
struct ScalarBinaryOpTraits<tether::Rev, double, BinaryOp> {
  using ReturnType = tether::Rev;
};
template <typename BinaryOp>
struct ScalarBinaryOpTraits<double, tether::Rev, BinaryOp> {
  using ReturnType = tether::Rev;
};

}  // namespace Eigen
