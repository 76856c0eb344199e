// Point and angle rows of 3D scenes recorded as one operation each (constraint_rows.h), and their adjoints.
//
// The inputs are the bodies' frame quantities (R_WB, R_WP and w of UpdateFrames, themselves recorded), their
// positions x (q entries) and the primitives' own quantities; the outputs are every row's C, Jdot v and the
// rotational parts of its two Jacobian blocks (the translational parts are the constants -e_k, e_k or zero).
// Forward values are computed by EvaluatePointRows' and EvaluateAngleRows' expressions in double, so they are the
// double run's. The adjoints follow each line back, with, for c = a x b, abar += b x cbar, bbar += cbar x a, and
// for y = R x, Rbar += ybar x^T, xbar += R^T ybar:
//
// point, on each side (sign s = -1 on A, +1 on B), a = R_WB r, p = x + a, spin = w x a, centripetal = w x spin,
//   row k: C = s p_k summed, Jdot v = s centripetal_k summed, rotation g_k = R_WP^T (a x s e_k):
//   pbar = s Cbar,  centripetalbar = s (Jdot v)bar,
//   R_WPbar += (a x s e_k) gbar_k^T,  abar += s e_k x (R_WP gbar_k),
//   wbar += spin x centripetalbar + a x spinbar with spinbar = centripetalbar x w,  abar += spinbar x w,
//   xbar += pbar,  abar += pbar,  R_WBbar += abar r^T,  rbar += R_WB^T abar
//   (a particle: p = x + r; the world: p = r).
// angle, u = R_WA u^A, w = R_WB w^B, N = u x w, D = w_A - w_B, P = w_A x u, V = w_B x w, Q = P x w + u x V:
//   C = u . w - c,  g_A = R_WPA^T N,  g_B = -R_WPB^T N,  Jdot v = D . Q:
//   ubar += Cbar w,  wbar += Cbar u,  cbar -= Cbar,
//   R_WPAbar += N gbar_A^T,  R_WPBbar -= N gbar_B^T,  Nbar = R_WPA gbar_A - R_WPB gbar_B,
//   ubar += w x Nbar,  wbar += Nbar x u,
//   Dbar = (Jdot v)bar Q, Qbar = (Jdot v)bar D:  w_Abar += Dbar,  w_Bbar -= Dbar,
//   Pbar = w x Qbar,  wbar += Qbar x P,  w_Abar += u x Pbar,  ubar += Pbar x w_A,
//   ubar += V x Qbar,  Vbar = Qbar x u,  w_Bbar += w x Vbar,  wbar += Vbar x w_B,
//   R_WAbar += ubar u^A^T,  u^Abar += R_WA^T ubar  (and the same for w on B; without a frame u = u^A).
#include <array>
#include <memory>

#include "tether/dynamics/adjoint/recorded.h"
#include "tether/dynamics/adjoint/recorded_blocks.h"
#include "tether/dynamics/constraints/constraint_rows_impl.h"

namespace tether {
namespace {

constexpr int kOutputs = 8;  // per row: C, Jdot v, the rotational part on A (3), on B (3)

Vec3<int> NoNodes() { return Vec3<int>::Constant(-1); }

// One side of a primitive: a 3D body's frame quantities (values and nodes), or none for a particle or the world.
struct Side {
  int body = kWorld;
  bool framed = false;  // a 3D rigid body
  Mat3<double> R_WB = Mat3<double>::Identity(), R_WP = Mat3<double>::Identity();
  Vec3<double> w = Vec3<double>::Zero();  // zero without velocity terms
  Mat3<int> R_WB_nodes = Mat3<int>::Constant(-1), R_WP_nodes = Mat3<int>::Constant(-1);
  Vec3<int> w_nodes = NoNodes();
};

Side SideOf(const Model<Rev>& model, const BodyFrames<Rev>& frames, int body, bool velocity_terms) {
  Side side;
  if (body == kWorld || model.bodies[body].kind != BodyKind::kRigid3d) return side;
  const BodyFrame<Rev>& f = frames[body];
  side.body = body;
  side.framed = true;
  side.R_WB = Values(f.R_WB);
  side.R_WP = Values(f.R_WP);
  side.R_WB_nodes = Nodes(f.R_WB);
  side.R_WP_nodes = Nodes(f.R_WP);
  if (velocity_terms) {
    side.w = Values(f.w_W);
    side.w_nodes = Nodes(f.w_W);
  }
  return side;
}

// The adjoints of the bodies' frame quantities (R_WB, R_WP, w) summed over an operation's rows, and added to their
// nodes once per body when the sweep of the operation ends (Flush): a body's rows share its frame's nodes.
class FrameAdjoints {
 public:
  void Add(const Side& side, const Mat3<double>& R_WB_bar, const Mat3<double>& R_WP_bar, const Vec3<double>& w_bar) {
    if (!side.framed) return;
    if (side.body >= static_cast<int>(slot_.size())) slot_.resize(side.body + 1, -1);
    int& slot = slot_[side.body];
    if (slot < 0) {
      slot = static_cast<int>(sums_.size());
      sums_.push_back({&side, Mat3<double>::Zero(), Mat3<double>::Zero(), Vec3<double>::Zero()});
    }
    Sum& sum = sums_[slot];
    sum.R_WB += R_WB_bar;
    sum.R_WP += R_WP_bar;
    sum.w += w_bar;
  }
  void Flush(Tape* tape) {
    for (const Sum& sum : sums_) {
      AddAdjoints(tape, sum.side->R_WB_nodes, sum.R_WB);
      AddAdjoints(tape, sum.side->R_WP_nodes, sum.R_WP);
      AddAdjoints(tape, sum.side->w_nodes, sum.w);
      slot_[sum.side->body] = -1;
    }
    sums_.clear();
  }

 private:
  struct Sum {
    const Side* side;  // one of the body's sides: its nodes
    Mat3<double> R_WB, R_WP;
    Vec3<double> w;
  };
  std::vector<int> slot_;  // by body index: the body's sum, or -1
  std::vector<Sum> sums_;
};

// A point of a point primitive: its side, x and r (values and nodes) and the motion computed from them.
struct PointSide {
  Side side;
  bool on_body = false;  // a particle or a 3D body (x is read)
  Vec3<double> local, arm = Vec3<double>::Zero(), spin = Vec3<double>::Zero();
  Vec3<double> position, centripetal = Vec3<double>::Zero();
  Vec3<int> x_nodes = NoNodes(), local_nodes = NoNodes();
};

// As MovePoint: p = x + a, spin = w x a, centripetal = w x spin.
PointSide MoveSide(const Model<Rev>& model, const BodyFrames<Rev>& frames, const BodyPoint<Rev>& point,
                   const VecX<Rev>& q, bool velocity_terms) {
  PointSide s;
  s.side = SideOf(model, frames, point.body, velocity_terms);
  s.local = Values(point.local);
  s.local_nodes = Nodes(point.local);
  if (point.body == kWorld) {
    s.position = s.local;
    return s;
  }
  s.on_body = true;
  const int offset = model.bodies[point.body].q_offset;
  s.position = Vec3<double>(q[offset].a, q[offset + 1].a, q[offset + 2].a);
  s.x_nodes = Vec3<int>(q[offset].index, q[offset + 1].index, q[offset + 2].index);
  if (!s.side.framed) {
    s.position += s.local;
    return s;
  }
  s.arm = s.side.R_WB * s.local;
  s.position += s.arm;
  if (velocity_terms) {
    s.spin = s.side.w.cross(s.arm);
    s.centripetal = s.side.w.cross(s.spin);
  }
  return s;
}

// The adjoints of one point's p, centripetal, arm (from the rotational parts g_k) and R_WP, the side's sign
// already applied; FinishPointSide takes them back to the point's inputs.
struct PointSideAdjoint {
  Vec3<double> position = Vec3<double>::Zero(), centripetal = Vec3<double>::Zero(), arm = Vec3<double>::Zero();
  Mat3<double> R_WP = Mat3<double>::Zero();
};

void FinishPointSide(Tape* tape, const PointSide& s, PointSideAdjoint adjoint, FrameAdjoints* frames) {
  if (!s.side.framed) {  // p = x + r, or p = r
    if (s.on_body) AddAdjoints(tape, s.x_nodes, adjoint.position);
    AddAdjoints(tape, s.local_nodes, adjoint.position);
    return;
  }
  const Vec3<double> spin_bar = adjoint.centripetal.cross(s.side.w);
  const Vec3<double> w_bar = s.spin.cross(adjoint.centripetal) + s.arm.cross(spin_bar);
  adjoint.arm += spin_bar.cross(s.side.w) + adjoint.position;
  AddAdjoints(tape, s.x_nodes, adjoint.position);
  AddAdjoints(tape, s.local_nodes, Vec3<double>(s.side.R_WB.transpose() * adjoint.arm));
  frames->Add(s.side, adjoint.arm * s.local.transpose(), adjoint.R_WP, w_bar);
}

struct PointEntry {
  PointSide a, b;
};

struct PointRecord {
  std::vector<PointEntry> entries;
  bool velocity_terms = false;
  std::vector<double> values;    // the forward's outputs (scratch, reused with the record)
  mutable FrameAdjoints frames;  // the backward sweep's sums (scratch)

  void Backward(const double* adjoint, Tape* tape) const {
    for (size_t i = 0; i < entries.size(); ++i) {
      const PointEntry& e = entries[i];
      PointSideAdjoint bar_a, bar_b;
      for (int k = 0; k < 3; ++k) {
        const double* out = adjoint + kOutputs * (3 * i + k);
        const Vec3<double> unit = Vec3<double>::Unit(k);
        bar_a.position[k] = -out[0];
        bar_b.position[k] = out[0];
        if (velocity_terms) {
          bar_a.centripetal[k] = -out[1];
          bar_b.centripetal[k] = out[1];
        }
        const Vec3<double> g_bar_a(out[2], out[3], out[4]), g_bar_b(out[5], out[6], out[7]);
        if (e.a.side.framed) {  // g = R_WP^T (a x -e_k)
          bar_a.R_WP += e.a.arm.cross(-unit) * g_bar_a.transpose();
          bar_a.arm += (-unit).cross(e.a.side.R_WP * g_bar_a);
        }
        if (e.b.side.framed) {  // g = R_WP^T (a x e_k)
          bar_b.R_WP += e.b.arm.cross(unit) * g_bar_b.transpose();
          bar_b.arm += unit.cross(e.b.side.R_WP * g_bar_b);
        }
      }
      FinishPointSide(tape, e.a, bar_a, &frames);
      FinishPointSide(tape, e.b, bar_b, &frames);
    }
    frames.Flush(tape);
  }
};

struct AngleEntry {
  Side a, b;
  Vec3<double> u_local, w_local, u, w;  // u^A, w^B and their world images
  Vec3<int> u_nodes, w_nodes;           // of u^A and w^B
  int c_node = -1;
};

struct AngleRecord {
  std::vector<AngleEntry> entries;  // one per row
  bool velocity_terms = false;
  std::vector<double> values;    // the forward's outputs (scratch, reused with the record)
  mutable FrameAdjoints frames;  // the backward sweep's sums (scratch)

  void Backward(const double* adjoint, Tape* tape) const {
    for (size_t i = 0; i < entries.size(); ++i) {
      const AngleEntry& e = entries[i];
      const double* out = adjoint + kOutputs * i;
      const double c_bar = out[0], bias_bar = velocity_terms ? out[1] : 0.0;
      const Vec3<double> g_bar_a(out[2], out[3], out[4]), g_bar_b(out[5], out[6], out[7]);
      const Vec3<double> normal = e.u.cross(e.w);
      Vec3<double> u_bar = c_bar * e.w, w_bar = c_bar * e.u, w_a_bar = Vec3<double>::Zero(), w_b_bar = w_a_bar;
      Vec3<double> normal_bar = Vec3<double>::Zero();
      Mat3<double> R_WP_a_bar = Mat3<double>::Zero(), R_WP_b_bar = Mat3<double>::Zero();
      if (e.a.framed) {
        R_WP_a_bar = normal * g_bar_a.transpose();
        normal_bar += e.a.R_WP * g_bar_a;
      }
      if (e.b.framed) {
        R_WP_b_bar = -normal * g_bar_b.transpose();
        normal_bar -= e.b.R_WP * g_bar_b;
      }
      u_bar += e.w.cross(normal_bar);
      w_bar += normal_bar.cross(e.u);
      if (bias_bar != 0.0) {
        const Vec3<double>& w_A = e.a.w;
        const Vec3<double>& w_B = e.b.w;
        const Vec3<double> p = w_A.cross(e.u), v = w_B.cross(e.w);
        const Vec3<double> d_bar = bias_bar * Vec3<double>(p.cross(e.w) + e.u.cross(v));
        const Vec3<double> q_bar = bias_bar * Vec3<double>(w_A - w_B);
        w_a_bar += d_bar;
        w_b_bar -= d_bar;
        const Vec3<double> p_bar = e.w.cross(q_bar);
        w_bar += q_bar.cross(p);
        w_a_bar += e.u.cross(p_bar);
        u_bar += p_bar.cross(w_A);
        u_bar += v.cross(q_bar);
        const Vec3<double> v_bar = q_bar.cross(e.u);
        w_b_bar += e.w.cross(v_bar);
        w_bar += v_bar.cross(w_B);
      }
      tape->AddAdjoint(e.c_node, -c_bar);
      if (e.a.framed) {
        AddAdjoints(tape, e.u_nodes, Vec3<double>(e.a.R_WB.transpose() * u_bar));
        frames.Add(e.a, u_bar * e.u_local.transpose(), R_WP_a_bar, w_a_bar);
      } else {
        AddAdjoints(tape, e.u_nodes, u_bar);
      }
      if (e.b.framed) {
        AddAdjoints(tape, e.w_nodes, Vec3<double>(e.b.R_WB.transpose() * w_bar));
        frames.Add(e.b, w_bar * e.w_local.transpose(), R_WP_b_bar, w_b_bar);
      } else {
        AddAdjoints(tape, e.w_nodes, w_bar);
      }
    }
    frames.Flush(tape);
  }
};

// Whether every body the primitives touch is the world, a particle or a 3D rigid body: the operations' cases.
bool Spatial(const Model<Rev>& model, const std::array<int, 2>& bodies) {
  if (model.dimension != 3) return false;
  for (int body : bodies) {
    if (body != kWorld && model.bodies[body].kind == BodyKind::kPlanar) return false;
  }
  return true;
}
template <typename Primitive, typename BodiesOf>
bool AllSpatial(const Model<Rev>& model, const std::vector<Primitive>& primitives, BodiesOf bodies_of) {
  for (const Primitive& c : primitives) {
    if (!Spatial(model, bodies_of(c))) return false;
  }
  return !primitives.empty();
}

// Whether a side's frame quantities include a recorded node.
bool Recorded(const Side& side) {
  return AnyRecorded(side.R_WB_nodes) || AnyRecorded(side.R_WP_nodes) || AnyRecorded(side.w_nodes);
}

// Writes one row's outputs: recorded nodes from `node` on (-1: constants), the translational parts given.
void SetRow(const double* value, int node, bool velocity_terms, const Vec3<double>& translation_a,
            const Vec3<double>& translation_b, ConstraintRow<Rev>* row) {
  auto output = [node, value](int k) { return node < 0 ? Rev(value[k]) : Rev(value[k], node + k); };
  row->value = output(0);
  if (velocity_terms) row->bias = output(1);
  for (int k = 0; k < 3; ++k) {
    row->a.translation[k] = Rev(translation_a[k]);
    row->b.translation[k] = Rev(translation_b[k]);
    row->a.rotation[k] = output(2 + k);
    row->b.rotation[k] = output(5 + k);
  }
}

}  // namespace

ConstraintRow<Rev>* RecordedPointRows(const Model<Rev>& model, const std::vector<PointPrimitive<Rev>>& points,
                                      const BodyFrames<Rev>& frames, const VecX<Rev>& q, const VecX<Rev>& v,
                                      bool velocity_terms, ConstraintRow<Rev>* rows) {
  if (!AllSpatial(model, points, [](const PointPrimitive<Rev>& c) { return std::array<int, 2>{c.a.body, c.b.body}; })) {
    for (const PointPrimitive<Rev>& c : points)
      rows = internal::EvaluatePointRows(model, frames, c, q, v, velocity_terms, rows);
    return rows;
  }
  Tape* tape = ActiveTape();
  const std::shared_ptr<PointRecord> record = tape ? tape->Reusable<PointRecord>() : std::make_shared<PointRecord>();
  record->velocity_terms = velocity_terms;
  record->entries.resize(points.size());
  std::vector<double>& values = record->values;
  values.assign(kOutputs * 3 * points.size(), 0.0);
  bool recorded = false;
  for (size_t i = 0; i < points.size(); ++i) {
    PointEntry& e = record->entries[i];
    e.a = MoveSide(model, frames, points[i].a, q, velocity_terms);
    e.b = MoveSide(model, frames, points[i].b, q, velocity_terms);
    for (const PointSide* s : {&e.a, &e.b}) {
      recorded = recorded || Recorded(s->side) || AnyRecorded(s->x_nodes) || AnyRecorded(s->local_nodes);
    }
    for (int k = 0; k < 3; ++k) {  // as EvaluatePointRows and PointGradient
      const Vec3<double> unit = Vec3<double>::Unit(k);
      double* out = values.data() + kOutputs * (3 * i + k);
      out[0] = e.b.position[k] - e.a.position[k];
      if (velocity_terms) out[1] = e.b.centripetal[k] - e.a.centripetal[k];
      if (e.a.side.framed) {
        const Vec3<double> g = TransposeTimes(e.a.side.R_WP, Vec3<double>(e.a.arm.cross(Vec3<double>(-unit))));
        for (int j = 0; j < 3; ++j) out[2 + j] = g[j];
      }
      if (e.b.side.framed) {
        const Vec3<double> g = TransposeTimes(e.b.side.R_WP, Vec3<double>(e.b.arm.cross(unit)));
        for (int j = 0; j < 3; ++j) out[5 + j] = g[j];
      }
    }
  }
  const int count = kOutputs * 3 * static_cast<int>(points.size());
  const int first =
      recorded ? tape->RecordExternal(count, [record](const double* adjoint, Tape* t) { record->Backward(adjoint, t); })
               : -1;
  for (size_t i = 0; i < points.size(); ++i) {
    for (int k = 0; k < 3; ++k, ++rows) {
      const int offset = kOutputs * (3 * static_cast<int>(i) + k);
      const Vec3<double> unit = Vec3<double>::Unit(k);
      rows->a.body = points[i].a.body;
      rows->b.body = points[i].b.body;
      SetRow(values.data() + offset, recorded ? first + offset : -1, velocity_terms, -unit, unit, rows);
    }
  }
  return rows;
}

ConstraintRow<Rev>* RecordedAngleRows(const Model<Rev>& model, const std::vector<AnglePrimitive<Rev>>& angles,
                                      const BodyFrames<Rev>& frames, bool velocity_terms, ConstraintRow<Rev>* rows) {
  if (!AllSpatial(model, angles, [](const AnglePrimitive<Rev>& c) { return std::array<int, 2>{c.body_a, c.body_b}; })) {
    for (const AnglePrimitive<Rev>& c : angles)
      rows = internal::EvaluateAngleRows(model, frames, c, velocity_terms, rows);
    return rows;
  }
  Tape* tape = ActiveTape();
  const std::shared_ptr<AngleRecord> record = tape ? tape->Reusable<AngleRecord>() : std::make_shared<AngleRecord>();
  record->velocity_terms = velocity_terms;
  record->entries.clear();
  std::vector<double>& values = record->values;
  values.clear();
  bool recorded = false;
  for (const AnglePrimitive<Rev>& c : angles) {
    const Side a = SideOf(model, frames, c.body_a, velocity_terms), b = SideOf(model, frames, c.body_b, velocity_terms);
    recorded = recorded || Recorded(a) || Recorded(b);
    for (int k = 0; k < c.rows; ++k) {  // as EvaluateAngleRows and Turning
      AngleEntry e{a, b, Values(c.u[k]), Values(c.w[k]), {}, {}, Nodes(c.u[k]), Nodes(c.w[k]), c.c[k].index};
      recorded = recorded || AnyRecorded(e.u_nodes) || AnyRecorded(e.w_nodes) || e.c_node >= 0;
      e.u = a.framed ? Vec3<double>(a.R_WB * e.u_local) : e.u_local;
      e.w = b.framed ? Vec3<double>(b.R_WB * e.w_local) : e.w_local;
      const Vec3<double> normal = e.u.cross(e.w);
      const Vec3<double> g_a = a.framed ? TransposeTimes(a.R_WP, normal) : Vec3<double>::Zero();
      const Vec3<double> g_b = b.framed ? TransposeTimes(b.R_WP, Vec3<double>(-normal)) : Vec3<double>::Zero();
      const double bias =
          velocity_terms ? (a.w - b.w).dot(Vec3<double>(a.w.cross(e.u).cross(e.w) + e.u.cross(b.w.cross(e.w)))) : 0.0;
      values.insert(values.end(), {e.u.dot(e.w) - c.c[k].a, bias, g_a[0], g_a[1], g_a[2], g_b[0], g_b[1], g_b[2]});
      record->entries.push_back(e);
    }
  }
  const int count = static_cast<int>(values.size());
  const int first =
      recorded && count > 0
          ? tape->RecordExternal(count, [record](const double* adjoint, Tape* t) { record->Backward(adjoint, t); })
          : -1;
  const Vec3<double> none = Vec3<double>::Zero();
  size_t i = 0;
  for (const AnglePrimitive<Rev>& c : angles) {
    for (int k = 0; k < c.rows; ++k, ++rows, ++i) {
      const int offset = kOutputs * static_cast<int>(i);
      rows->a.body = c.body_a;
      rows->b.body = c.body_b;
      SetRow(values.data() + offset, first >= 0 ? first + offset : -1, velocity_terms, none, none, rows);
    }
  }
  return rows;
}

}  // namespace tether
