// Blocks of Rev (reverse.h) as the records of recorded operations keep them (kkt_adjoint.cc, distance_adjoint.cc,
// rigid_rows_adjoint.cc, frames_adjoint.cc, gyroscopic_adjoint.cc, joint_torque_adjoint.cc): a vector's or
// matrix's values in double, its node indices (-1 for a constant), and a block of adjoints added to a block of
// nodes, entry by entry (AddAdjoint skips constants).
#pragma once

#include "tether/dynamics/scalars/scalar.h"

namespace tether {

template <int R, int C>
Eigen::Matrix<double, R, C> Values(const Eigen::Matrix<Rev, R, C>& x) {
  return x.unaryExpr([](const Rev& r) { return r.a; });
}

template <int R, int C>
Eigen::Matrix<int, R, C> Nodes(const Eigen::Matrix<Rev, R, C>& x) {
  return x.unaryExpr([](const Rev& r) { return r.index; });
}

// The same into existing matrices, whose buffers serve again (no temporary is allocated).
template <int R, int C>
void ValuesInto(const Eigen::Matrix<Rev, R, C>& x, Eigen::Matrix<double, R, C>* values) {
  *values = x.unaryExpr([](const Rev& r) { return r.a; });
}
template <int R, int C>
void NodesInto(const Eigen::Matrix<Rev, R, C>& x, Eigen::Matrix<int, R, C>* nodes) {
  *nodes = x.unaryExpr([](const Rev& r) { return r.index; });
}

// Whether any of the nodes is recorded.
template <typename Derived>
bool AnyRecorded(const Eigen::MatrixBase<Derived>& nodes) {
  return (nodes.array() >= 0).any();
}

// adjoint(nodes_k) += adjoint_k, with the entries of both in the same (column-major) order.
template <typename NodeBlock, typename Derived>
void AddAdjoints(Tape* tape, const NodeBlock& nodes, const Eigen::MatrixBase<Derived>& adjoint) {
  const typename Derived::PlainObject values = adjoint;
  for (Eigen::Index k = 0; k < values.size(); ++k) tape->AddAdjoint(nodes.data()[k], values.data()[k]);
}

}  // namespace tether
