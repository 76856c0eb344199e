// The frames of 3D bodies (kinematics.h) recorded as one operation, and its adjoint.
//
// Forward, per body, by UpdateFrames' expressions in double: from the orientation q = (w, x, y, z) and the
// angular velocity v_P (principal axes),
//   R_WB = RotationMatrix(q),   R_WP = R_WB P (P the principal axes' constant rotation; R_WB when they are the
//   body's axes),   w_W = R_WP v_P.
// Backward, from R_WBbar, R_WPbar, w_Wbar (for y = A x: Abar += ybar x^T, xbar += A^T ybar):
//   R_WPbar += w_Wbar v_P^T,   v_Pbar = R_WP^T w_Wbar,   R_WBbar += R_WPbar P^T,
// and with B = R_WBbar, by the partial derivatives of RotationMatrix's entries,
//   wbar = 2 (-z B01 + y B02 + z B10 - x B12 - y B20 + x B21)
//   xbar = 2 (y B01 + z B02 + y B10 - 2x B11 - w B12 + z B20 + w B21 - 2x B22)
//   ybar = 2 (-2y B00 + x B01 + w B02 + x B10 + z B12 - w B20 + z B21 - 2y B22)
//   zbar = 2 (-2z B00 - w B01 + x B02 + w B10 - 2z B11 + y B12 + x B20 + y B21).
#include <array>
#include <memory>
#include <vector>

#include "tether/dynamics/adjoint/recorded.h"
#include "tether/dynamics/adjoint/recorded_blocks.h"
#include "tether/dynamics/model/kinematics.h"

namespace tether {
namespace {

constexpr int kOutputs = 21;  // per body: R_WB (9), R_WP (9), w_W (3), column-major

struct BodyRecord {
  Mat3<double> R_WB;  // the forward's outputs
  Vec3<double> w_W;
  Vec4<int> orientation_nodes;
  Vec3<int> velocity_nodes;
  Vec4<double> orientation;
  Vec3<double> velocity;    // v_P
  Mat3<double> R_WP, axes;  // axes: P
  bool principal = true;
};

struct FramesRecord {
  std::vector<BodyRecord> bodies;
  bool velocities = false;

  void Backward(const double* adjoint, Tape* tape) const {
    for (size_t i = 0; i < bodies.size(); ++i) {
      const BodyRecord& b = bodies[i];
      const double* out = adjoint + kOutputs * i;
      Mat3<double> R_WB_bar = Eigen::Map<const Mat3<double>>(out);
      Mat3<double> R_WP_bar = Eigen::Map<const Mat3<double>>(out + 9);
      if (velocities) {
        const Vec3<double> w_bar(out[18], out[19], out[20]);
        R_WP_bar += w_bar * b.velocity.transpose();
        AddAdjoints(tape, b.velocity_nodes, b.R_WP.transpose() * w_bar);
      }
      R_WB_bar += b.principal ? R_WP_bar : Mat3<double>(R_WP_bar * b.axes.transpose());
      const Mat3<double>& B = R_WB_bar;
      const double w = b.orientation[0], x = b.orientation[1], y = b.orientation[2], z = b.orientation[3];
      const Vec4<double> bar(2.0 * (-z * B(0, 1) + y * B(0, 2) + z * B(1, 0) - x * B(1, 2) - y * B(2, 0) + x * B(2, 1)),
                             2.0 * (y * B(0, 1) + z * B(0, 2) + y * B(1, 0) - 2.0 * x * B(1, 1) - w * B(1, 2) +
                                    z * B(2, 0) + w * B(2, 1) - 2.0 * x * B(2, 2)),
                             2.0 * (-2.0 * y * B(0, 0) + x * B(0, 1) + w * B(0, 2) + x * B(1, 0) + z * B(1, 2) -
                                    w * B(2, 0) + z * B(2, 1) - 2.0 * y * B(2, 2)),
                             2.0 * (-2.0 * z * B(0, 0) - w * B(0, 1) + x * B(0, 2) + w * B(1, 0) - 2.0 * z * B(1, 1) +
                                    y * B(1, 2) + x * B(2, 0) + y * B(2, 1)));
      AddAdjoints(tape, b.orientation_nodes, bar);
    }
  }
};

}  // namespace

bool RecordedSpatialFrames(const Model<Rev>& model, const VecX<Rev>& q, const VecX<Rev>& v, bool velocities,
                           BodyFrames<Rev>* frames) {
  if (model.spatial_bodies.empty()) return true;
  Tape* tape = ActiveTape();
  const std::shared_ptr<FramesRecord> record = tape ? tape->Reusable<FramesRecord>() : std::make_shared<FramesRecord>();
  record->velocities = velocities;
  record->bodies.resize(model.spatial_bodies.size());
  bool recorded = false;
  for (size_t i = 0; i < model.spatial_bodies.size(); ++i) {
    const Body<Rev>& body = model.bodies[model.spatial_bodies[i]];
    BodyRecord& b = record->bodies[i];
    const Vec4<Rev> orientation = Orientation(body, q);
    b.orientation = Values(orientation);
    b.orientation_nodes = Nodes(orientation);
    b.velocity_nodes.setConstant(-1);
    b.velocity.setZero();
    if (velocities) {
      const Vec3<Rev> velocity = v.segment<3>(body.v_offset + 3);
      b.velocity = Values(velocity);
      b.velocity_nodes = Nodes(velocity);
    }
    recorded = recorded || AnyRecorded(b.orientation_nodes) || AnyRecorded(b.velocity_nodes);
    // as UpdateFrames
    b.R_WB = RotationMatrix(b.orientation);
    b.principal = body.principal_axes == Vec4<double>(1, 0, 0, 0);
    b.axes = RotationMatrix(Vec4<double>(body.principal_axes));
    b.R_WP = b.principal ? b.R_WB : Mat3<double>(b.R_WB * b.axes);
    if (velocities) b.w_W = b.R_WP * b.velocity;
  }
  const int count = kOutputs * static_cast<int>(model.spatial_bodies.size());
  const int first =
      recorded ? tape->RecordExternal(count, [record](const double* adjoint, Tape* t) { record->Backward(adjoint, t); })
               : -1;
  for (size_t i = 0; i < model.spatial_bodies.size(); ++i) {
    BodyFrame<Rev>& f = (*frames)[model.spatial_bodies[i]];
    const BodyRecord& b = record->bodies[i];
    const int node = recorded ? first + kOutputs * static_cast<int>(i) : -1;
    auto output = [node](double value, int k) { return node < 0 ? Rev(value) : Rev(value, node + k); };
    for (int k = 0; k < 9; ++k) {
      f.R_WB(k) = output(b.R_WB(k), k);
      f.R_WP(k) = b.principal ? f.R_WB(k) : output(b.R_WP(k), 9 + k);
    }
    if (velocities) {
      for (int k = 0; k < 3; ++k) f.w_W[k] = output(b.w_W[k], 18 + k);
    }
  }
  return true;
}

}  // namespace tether
