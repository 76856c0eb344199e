// A torque on a 3D joint's angle coordinate (effects.h, joint_coordinates.h) recorded as one operation, and its
// adjoint.
//
// Forward, by EvaluateCoordinate's and AddScaled's expressions in double: with a = R_WA a^A the joint's axis in
// the world (R_WA the identity when A is the world), theta' = (w_B - w_A) . a, so the generalized force of a
// torque tau is tau (g_A, g_B) on the rotations, g_A = R_WPA^T (-a), g_B = R_WPB^T a (zero on the world);
// the operation's outputs are t_A = tau g_A and t_B = tau g_B, added to f in Rev arithmetic. The angle's value
// is not needed for a torque and is not computed. Backward, from tbar_A, tbar_B:
//   taubar = tbar_A . g_A + tbar_B . g_B,   gbar = tau tbar,
//   R_WPAbar += (-a) gbar_A^T,  R_WPBbar += a gbar_B^T,  abar = -R_WPA gbar_A + R_WPB gbar_B,
//   R_WAbar += abar a^A^T,  a^Abar += R_WA^T abar.
#include <array>
#include <memory>

#include "tether/dynamics/adjoint/recorded.h"
#include "tether/dynamics/adjoint/recorded_blocks.h"
#include "tether/dynamics/effects/effects.h"

namespace tether {
namespace {

// One side of the joint: a 3D body's R_WP (values and nodes), or nothing for the world or a particle.
struct TorqueSide {
  bool framed = false;
  Mat3<double> R_WP = Mat3<double>::Identity();
  Mat3<int> R_WP_nodes = Mat3<int>::Constant(-1);
  int v_offset = 0;
};

TorqueSide SideOf(const Model<Rev>& model, const BodyFrames<Rev>& frames, int body) {
  TorqueSide side;
  if (body == kWorld || model.bodies[body].kind != BodyKind::kRigid3d) return side;
  side.framed = true;
  side.v_offset = model.bodies[body].v_offset;
  side.R_WP = Values(frames[body].R_WP);
  side.R_WP_nodes = Nodes(frames[body].R_WP);
  return side;
}

struct AngleTorqueRecord {
  TorqueSide a, b;
  Mat3<double> R_WA = Mat3<double>::Identity();
  Mat3<int> R_WA_nodes = Mat3<int>::Constant(-1);
  Vec3<double> axis, axis_W, g_a, g_b;  // a^A, a, g_A, g_B
  Vec3<int> axis_nodes;
  double tau = 0.0;
  int tau_node = -1;

  void Backward(const double* t_bar, Tape* tape) const {
    const Vec3<double> t_bar_a(t_bar[0], t_bar[1], t_bar[2]), t_bar_b(t_bar[3], t_bar[4], t_bar[5]);
    tape->AddAdjoint(tau_node, t_bar_a.dot(g_a) + t_bar_b.dot(g_b));
    Vec3<double> axis_W_bar = Vec3<double>::Zero();
    if (a.framed) {
      const Vec3<double> g_bar = tau * t_bar_a;
      const Mat3<double> R_bar = -axis_W * g_bar.transpose();
      AddAdjoints(tape, a.R_WP_nodes, R_bar);
      axis_W_bar -= a.R_WP * g_bar;
    }
    if (b.framed) {
      const Vec3<double> g_bar = tau * t_bar_b;
      const Mat3<double> R_bar = axis_W * g_bar.transpose();
      AddAdjoints(tape, b.R_WP_nodes, R_bar);
      axis_W_bar += b.R_WP * g_bar;
    }
    AddAdjoints(tape, R_WA_nodes, axis_W_bar * axis.transpose());
    AddAdjoints(tape, axis_nodes, R_WA.transpose() * axis_W_bar);
  }
};

}  // namespace

bool RecordedAngleTorque(const Model<Rev>& model, const JointCoordinates<Rev>& coordinates, int k,
                         const BodyFrames<Rev>& frames, const Rev& value, VecX<Rev>* f) {
  const CoordinateReference<Rev>& reference = coordinates.references[k];
  if (model.dimension != 3 || reference.coordinate != JointCoordinate::kAngle) return false;
  const Joint<Rev>& joint = model.joints[reference.joint];
  Tape* tape = ActiveTape();
  const std::shared_ptr<AngleTorqueRecord> record =
      tape ? tape->Reusable<AngleTorqueRecord>() : std::make_shared<AngleTorqueRecord>();
  AngleTorqueRecord& r = *record;
  r.a = SideOf(model, frames, joint.a.body);
  r.b = SideOf(model, frames, joint.b.body);
  bool recorded = value.index >= 0 || AnyRecorded(r.a.R_WP_nodes) || AnyRecorded(r.b.R_WP_nodes);
  r.R_WA.setIdentity();
  r.R_WA_nodes.setConstant(-1);
  if (joint.a.body != kWorld && model.bodies[joint.a.body].kind != BodyKind::kParticle) {  // as RotationOf
    r.R_WA = Values(frames[joint.a.body].R_WB);
    r.R_WA_nodes = Nodes(frames[joint.a.body].R_WB);
  }
  r.axis = Values(reference.axis);
  r.axis_nodes = Nodes(reference.axis);
  recorded = recorded || AnyRecorded(r.R_WA_nodes) || AnyRecorded(r.axis_nodes);
  r.tau = value.a;
  r.tau_node = value.index;
  r.axis_W = r.R_WA * r.axis;
  r.g_a = r.a.framed ? TransposeTimes(r.a.R_WP, Vec3<double>(-r.axis_W)) : Vec3<double>::Zero();
  r.g_b = r.b.framed ? TransposeTimes(r.b.R_WP, r.axis_W) : Vec3<double>::Zero();
  const int first =
      recorded ? tape->RecordExternal(6, [record](const double* t_bar, Tape* t) { record->Backward(t_bar, t); }) : -1;
  const std::array<const TorqueSide*, 2> sides{&r.a, &r.b};
  for (int side = 0; side < 2; ++side) {
    if (!sides[side]->framed) continue;
    const Vec3<double>& g = side == 0 ? r.g_a : r.g_b;
    for (int i = 0; i < 3; ++i) {
      const double torque = r.tau * g[i];
      (*f)[sides[side]->v_offset + 3 + i] += first < 0 ? Rev(torque) : Rev(torque, first + 3 * side + i);
    }
  }
  return true;
}

}  // namespace tether
