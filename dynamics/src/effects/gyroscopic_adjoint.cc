// The gyroscopic torque of a 3D body (effects.h) recorded as one operation, and its adjoint.
//
// Forward, by AccumulateForces' expressions in double: with w = w_P (the body's angular velocity in v),
// I = PrincipalInertia (R_BP^T S R_BP, S the symmetric inertia tensor), y = I w, the torque is g = w x y and
// f_P -= g (done in Rev arithmetic on the operation's outputs g). Backward, from gbar:
//   wbar += y x gbar,  ybar = gbar x w,  wbar += I ybar  (I symmetric),  Ibar = ybar w^T,
//   Sbar = R_BP Ibar R_BP^T,  and S's upper triangle stands for both halves: tensorbar_ij = Sbar_ij + Sbar_ji
//   (i < j), tensorbar_ii = Sbar_ii.
#include <memory>
#include <vector>

#include "tether/dynamics/adjoint/recorded.h"
#include "tether/dynamics/adjoint/recorded_blocks.h"
#include "tether/dynamics/effects/effects.h"

namespace tether {
namespace {

struct GyroscopicRecord {
  Vec3<double> w, y;
  Mat3<double> I, R_BP;
  bool principal = true;
  Vec3<int> w_nodes;
  Mat3<int> tensor_nodes;

  void Backward(const double* g_bar_data, Tape* tape) const {
    const Vec3<double> g_bar(g_bar_data[0], g_bar_data[1], g_bar_data[2]);
    const Vec3<double> y_bar = g_bar.cross(w);
    const Vec3<double> w_bar = y.cross(g_bar) + I * y_bar;
    AddAdjoints(tape, w_nodes, w_bar);
    const Mat3<double> I_bar = y_bar * w.transpose();
    const Mat3<double> S_bar = principal ? I_bar : Mat3<double>(R_BP * I_bar * R_BP.transpose());
    for (int i = 0; i < 3; ++i) {
      tape->AddAdjoint(tensor_nodes(i, i), S_bar(i, i));
      for (int j = i + 1; j < 3; ++j) tape->AddAdjoint(tensor_nodes(i, j), S_bar(i, j) + S_bar(j, i));
    }
  }
};

}  // namespace

bool RecordedGyroscopicTorques(const Model<Rev>& model, const VecX<Rev>& v, VecX<Rev>* f) {
  Tape* tape = ActiveTape();
  for (int index : model.spatial_bodies) {
    const Body<Rev>& body = model.bodies[index];
    const std::shared_ptr<GyroscopicRecord> record =
        tape ? tape->Reusable<GyroscopicRecord>() : std::make_shared<GyroscopicRecord>();
    GyroscopicRecord& r = *record;
    const Mat3<double> tensor = Values(body.inertia_tensor);
    r.tensor_nodes = Nodes(body.inertia_tensor);
    const Vec3<Rev> w = v.segment<3>(body.v_offset + 3);
    r.w = Values(w);
    r.w_nodes = Nodes(w);
    const bool recorded = AnyRecorded(r.tensor_nodes) || AnyRecorded(r.w_nodes);
    r.principal = body.principal_axes == Vec4<double>(1, 0, 0, 0);
    r.R_BP = RotationMatrix(body.principal_axes);
    r.I = PrincipalInertia(tensor, body.principal_axes);
    r.y = r.I * r.w;
    const Vec3<double> g = r.w.cross(r.y);
    const int first =
        recorded ? tape->RecordExternal(3, [record](const double* g_bar, Tape* t) { record->Backward(g_bar, t); }) : -1;
    for (int k = 0; k < 3; ++k) (*f)[body.v_offset + 3 + k] -= first < 0 ? Rev(g[k]) : Rev(g[k], first + k);
  }
  return true;
}

}  // namespace tether
