// Integrate and DexpInv of scenes with 3D bodies recorded as one operation each (configuration_space.h), and
// their adjoints. Forward values come from the same functions in double (TurnedOrientation, DexpInv), so they
// are the double run's.
//
// Integrate: translations, particles and planar coordinates x' = x + h v (xbar += x'bar, vbar += h x'bar); a
// 3D body's orientation, with turn_B = R_BP (h w_P), e = Exp(turn_B) = (c, s turn_B) (c, s functions of
// sq = |turn_B|^2), p = q (x) e, q' = p / |p|:
//   pbar   = (q'bar - q' (q' . q'bar)) / |p|
//   qbar_w += pbar_w e_w + pbar_v . e_v,   qbar_v += -pbar_w e_v + e_w pbar_v + e_v x pbar_v
//   ebar_w  = pbar_w q_w + pbar_v . q_v,   ebar_v  = -pbar_w q_v + q_w pbar_v + pbar_v x q_v
//   turn_Bbar = s ebar_v + 2 turn_B (dc/dsq ebar_w + ds/dsq (turn_B . ebar_v)),   w_Pbar += h R_BP^T turn_Bbar
// (the product's adjoint from p_w = q_w e_w - q_v . e_v, p_v = q_w e_v + e_w q_v + q_v x e_v; the derivatives of
// c and s by the branch Exp takes, rotation.h's ExpCoefficientsAt).
// DexpInv on a 3D body's rotation: k = w + X / 2 + c Y, X = theta x w, Y = theta x X, c = c(|theta|^2):
//   wbar += kbar,  Ybar = c kbar,  Xbar = kbar / 2 + Ybar x theta,
//   thetabar += X x Ybar + 2 dc/ds2 (kbar . Y) theta + w x Xbar,  wbar += Xbar x theta.
#include <array>
#include <memory>
#include <tuple>
#include <vector>

#include "tether/dynamics/adjoint/recorded.h"
#include "tether/dynamics/adjoint/recorded_blocks.h"
#include "tether/dynamics/model/configuration_space.h"
#include "tether/dynamics/model/rotation.h"

namespace tether {
namespace {

// One 3D body's turn: the values its adjoint needs, and its orientation's and angular velocity's nodes.
struct Turn {
  int q_offset = 0;  // of the orientation in q and in the outputs
  Vec4<int> orientation_nodes;
  Vec3<int> rate_nodes;  // w_P
  Vec4<double> orientation, e, turned;
  Vec3<double> turn_B;
  double norm = 1.0;  // |p|
  ExpCoefficients coefficients{};
  bool principal = true;
  Mat3<double> R_BP = Mat3<double>::Identity();
};

struct IntegrateRecord {
  double h = 0.0;
  std::vector<std::array<int, 3>> linear;  // (coordinate, its node in q, its rate's node in v): x' = x + h v
  std::vector<Turn> turns;
  std::vector<double> values;  // the forward's outputs (scratch, reused with the record)

  void Backward(const double* adjoint, Tape* tape) const {
    for (const auto& [i, x_node, v_node] : linear) {
      tape->AddAdjoint(x_node, adjoint[i]);
      tape->AddAdjoint(v_node, h * adjoint[i]);
    }
    for (const Turn& t : turns) {
      const Vec4<double> out_bar(adjoint[t.q_offset], adjoint[t.q_offset + 1], adjoint[t.q_offset + 2],
                                 adjoint[t.q_offset + 3]);
      const Vec4<double> p_bar = (out_bar - t.turned * t.turned.dot(out_bar)) / t.norm;
      const double pw = p_bar[0], qw = t.orientation[0], ew = t.e[0];
      const Vec3<double> pv = VectorPart(p_bar), qv = VectorPart(t.orientation), ev = VectorPart(t.e);
      const Vec3<double> q_bar_v = -pw * ev + ew * pv + ev.cross(pv);
      AddAdjoints(tape, t.orientation_nodes, Vec4<double>(pw * ew + pv.dot(ev), q_bar_v[0], q_bar_v[1], q_bar_v[2]));
      const double e_bar_w = pw * qw + pv.dot(qv);
      const Vec3<double> e_bar_v = -pw * qv + qw * pv + pv.cross(qv);
      const ExpCoefficients& k = t.coefficients;
      const Vec3<double> turn_bar = k.s * e_bar_v + 2.0 * (k.dc * e_bar_w + k.ds * t.turn_B.dot(e_bar_v)) * t.turn_B;
      const Vec3<double> rate_bar = h * (t.principal ? turn_bar : Vec3<double>(t.R_BP.transpose() * turn_bar));
      AddAdjoints(tape, t.rate_nodes, rate_bar);
    }
  }
};

// One 3D body's stage derivative k = DexpInv(theta, w) on its rotation (outputs 3 j .. 3 j + 2 of the j-th).
struct Rotation {
  int v_offset = 0;  // of the rotation in v
  Vec3<int> theta_nodes, w_nodes;
  Vec3<double> theta, w, cross, double_cross;  // X = theta x w, Y = theta x X
  double c = 0.0, dc = 0.0;
};

struct DexpInvRecord {
  std::vector<Rotation> rotations;

  void Backward(const double* adjoint, Tape* tape) const {
    for (size_t j = 0; j < rotations.size(); ++j) {
      const Rotation& r = rotations[j];
      const Vec3<double> k_bar(adjoint[3 * j], adjoint[3 * j + 1], adjoint[3 * j + 2]);
      const Vec3<double> y_bar = r.c * k_bar;
      const Vec3<double> x_bar = 0.5 * k_bar + y_bar.cross(r.theta);
      const Vec3<double> theta_bar =
          r.cross.cross(y_bar) + 2.0 * r.dc * k_bar.dot(r.double_cross) * r.theta + r.w.cross(x_bar);
      AddAdjoints(tape, r.theta_nodes, theta_bar);
      AddAdjoints(tape, r.w_nodes, Vec3<double>(k_bar + x_bar.cross(r.theta)));
    }
  }
};

template <int N>
Eigen::Matrix<double, N, 1> ValuesAt(const VecX<Rev>& x, int offset) {
  return Values(Eigen::Matrix<Rev, N, 1>(x.segment<N>(offset)));
}
template <int N>
Eigen::Matrix<int, N, 1> NodesAt(const VecX<Rev>& x, int offset) {
  return Nodes(Eigen::Matrix<Rev, N, 1>(x.segment<N>(offset)));
}

}  // namespace

bool RecordedSpatialIntegrate(const Model<Rev>& model, const VecX<Rev>& q, const VecX<Rev>& v, double h,
                              VecX<Rev>* out) {
  Tape* tape = ActiveTape();
  const std::shared_ptr<IntegrateRecord> record =
      tape ? tape->Reusable<IntegrateRecord>() : std::make_shared<IntegrateRecord>();
  IntegrateRecord& r = *record;
  r.h = h;
  r.linear.clear();
  r.turns.clear();
  std::vector<double>& values = r.values;
  values.resize(q.size());
  bool recorded = false;
  for (const Body<Rev>& body : model.bodies) {
    const int translations = body.kind == BodyKind::kRigid3d ? 3 : body.q_size;
    for (int k = 0; k < translations; ++k) {  // as Integrate: x + h v
      const Rev& x = q[body.q_offset + k];
      const Rev& rate = v[body.v_offset + k];
      values[body.q_offset + k] = x.a + h * rate.a;
      r.linear.push_back({body.q_offset + k, x.index, rate.index});
      recorded = recorded || x.index >= 0 || rate.index >= 0;
    }
    if (body.kind != BodyKind::kRigid3d) continue;
    Turn& t = r.turns.emplace_back();
    t.q_offset = body.q_offset + 3;
    t.orientation = ValuesAt<4>(q, t.q_offset);
    t.orientation_nodes = NodesAt<4>(q, t.q_offset);
    t.rate_nodes = NodesAt<3>(v, body.v_offset + 3);
    recorded = recorded || AnyRecorded(t.orientation_nodes) || AnyRecorded(t.rate_nodes);
    const Vec3<double> w_P = ValuesAt<3>(v, body.v_offset + 3);
    const Vec3<double> turn_P(h * w_P[0], h * w_P[1], h * w_P[2]);
    t.turned = TurnedOrientation(t.orientation, body.principal_axes, turn_P);
    t.principal = body.principal_axes == Vec4<double>(1, 0, 0, 0);
    t.R_BP = RotationMatrix(body.principal_axes);
    t.turn_B = t.principal ? turn_P : Rotate(body.principal_axes, turn_P);
    t.e = Exp(t.turn_B);
    t.norm = QuaternionProduct(t.orientation, t.e).norm();
    t.coefficients = ExpCoefficientsAt(t.turn_B.squaredNorm());
    for (int k = 0; k < 4; ++k) values[t.q_offset + k] = t.turned[k];
  }
  const int first =
      recorded ? tape->RecordExternal(static_cast<int>(values.size()),
                                      [record](const double* adjoint, Tape* t) { record->Backward(adjoint, t); })
               : -1;
  for (Eigen::Index i = 0; i < out->size(); ++i) {
    (*out)[i] = recorded ? Rev(values[i], first + static_cast<int>(i)) : Rev(values[i]);
  }
  return true;
}

bool RecordedSpatialDexpInv(const Model<Rev>& model, const VecX<Rev>& theta, VecX<Rev>* k) {
  Tape* tape = ActiveTape();
  const std::shared_ptr<DexpInvRecord> record =
      tape ? tape->Reusable<DexpInvRecord>() : std::make_shared<DexpInvRecord>();
  record->rotations.clear();
  bool recorded = false;
  for (const int index : model.spatial_bodies) {
    Rotation& r = record->rotations.emplace_back();
    r.v_offset = model.bodies[index].v_offset + 3;
    r.theta = ValuesAt<3>(theta, r.v_offset);
    r.w = ValuesAt<3>(*k, r.v_offset);
    r.theta_nodes = NodesAt<3>(theta, r.v_offset);
    r.w_nodes = NodesAt<3>(*k, r.v_offset);
    recorded = recorded || AnyRecorded(r.theta_nodes) || AnyRecorded(r.w_nodes);
    r.cross = r.theta.cross(r.w);
    r.double_cross = r.theta.cross(r.cross);
    std::tie(r.c, r.dc) = DexpInvCoefficientAt(r.theta.squaredNorm());
  }
  const int count = 3 * static_cast<int>(record->rotations.size());
  const int first =
      recorded ? tape->RecordExternal(count, [record](const double* adjoint, Tape* t) { record->Backward(adjoint, t); })
               : -1;
  for (size_t j = 0; j < record->rotations.size(); ++j) {
    const Rotation& r = record->rotations[j];
    const Vec3<double> rate = DexpInv(r.theta, r.w);  // the double run's values
    for (int c = 0; c < 3; ++c) {
      (*k)[r.v_offset + c] = recorded ? Rev(rate[c], first + 3 * static_cast<int>(j) + c) : Rev(rate[c]);
    }
  }
  return true;
}

}  // namespace tether
