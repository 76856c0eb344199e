// Distance rows between particles recorded as one operation (constraint_rows.h), and its adjoint.
//
// For points p_a, p_b (a particle's position plus a constant offset, or a fixed world point) and their velocities
// v_a, v_b, with d = p_b - p_a, L = |d|, n = d / L, dv = v_b - v_a, along = n . dv, s = |dv|^2 - along^2:
//   C = L - length,   J_a = -n,   J_b = n,   Jdot v = s / L
// (a particle's point has no arm, so no rotational part and no centripetal term). Backward, from the adjoints
// Cbar, biasbar, Jbar_a, Jbar_b of the outputs:
//   nbar  = Jbar_b - Jbar_a - 2 biasbar along dv / L
//   dvbar = 2 biasbar (dv - along n) / L
//   Lbar  = Cbar - biasbar s / L^2
//   dbar  = (nbar - n (n . nbar)) / L + Lbar n         (n = d / L, L = |d|)
//   p_bbar += dbar, p_abar -= dbar, v_bbar += dvbar, v_abar -= dvbar, lengthbar -= Cbar.
// A particle's position and velocity are its q and v entries, so these adjoints go to their nodes. The forward
// values are computed by the same expressions as EvaluateDistanceRow's in double, so they are the double run's.
#include <array>
#include <memory>

#include "tether/dynamics/adjoint/recorded.h"
#include "tether/dynamics/adjoint/recorded_blocks.h"
#include "tether/dynamics/constraints/constraint_rows_impl.h"

namespace tether {
namespace {

// One row's inputs (nodes) and what its backward sweep needs (values).
struct DistanceRow {
  std::array<int, 3> position_a, position_b, velocity_a, velocity_b;  // nodes (-1: a constant)
  int length = -1;
  Vec3<double> n, dv;
  double inverse_length = 0.0, along = 0.0, s = 0.0;
};

// Whether the row's ends are particles or the world, with offsets that are constants: the rows done here.
bool BetweenParticles(const Model<Rev>& model, const DistancePrimitive<Rev>& c) {
  for (const BodyPoint<Rev>* point : {&c.a, &c.b}) {
    if (point->body != kWorld && model.bodies[point->body].kind != BodyKind::kParticle) return false;
    for (int k = 0; k < 3; ++k) {
      if (point->local[k].index >= 0) return false;
    }
  }
  return true;
}

// A point's position (or velocity, with offset zero) in double, and the nodes of its coordinates.
Vec3<double> Gather(const Model<Rev>& model, int body, const VecX<Rev>& x, int offset_of_body, const Vec3<Rev>& offset,
                    std::array<int, 3>* nodes) {
  nodes->fill(-1);
  if (body == kWorld) return Vec3<double>(offset[0].a, offset[1].a, offset[2].a);
  double values[3] = {0.0, 0.0, 0.0};
  for (int k = 0; k < model.dimension; ++k) {
    values[k] = x[offset_of_body + k].a;
    (*nodes)[k] = x[offset_of_body + k].index;
  }
  Vec3<double> p = Translation(model.dimension, values);  // as MovePoint: the translation, then the offset
  p += Vec3<double>(offset[0].a, offset[1].a, offset[2].a);
  return p;
}

constexpr int kOutputs = 8;  // C, Jdot v, J_a's translation (3), J_b's translation (3)

// One evaluation's rows done here, and the forward's scratch (reused with the record, Tape::Reusable).
struct DistanceRecord {
  std::vector<DistanceRow> rows;
  bool velocity_terms = false;
  std::vector<ConstraintRow<Rev>*> outputs;
  std::vector<double> values;  // kOutputs per row

  void Backward(const double* adjoint, Tape* tape) const;
};

void DistanceRecord::Backward(const double* adjoint, Tape* tape) const {
  for (size_t i = 0; i < rows.size(); ++i) {
    const DistanceRow& r = rows[i];
    const double* out = adjoint + kOutputs * i;
    const double c_bar = out[0], bias_bar = velocity_terms ? out[1] : 0.0;
    const Vec3<double> a_bar(out[2], out[3], out[4]), b_bar(out[5], out[6], out[7]);
    Vec3<double> n_bar = b_bar - a_bar;
    double length_bar = c_bar;
    if (bias_bar != 0.0) {
      n_bar -= 2.0 * bias_bar * r.along * r.inverse_length * r.dv;
      const Vec3<double> dv_bar = 2.0 * bias_bar * r.inverse_length * (r.dv - r.along * r.n);
      length_bar -= bias_bar * r.s * r.inverse_length * r.inverse_length;
      AddAdjoints(tape, r.velocity_b, dv_bar);
      AddAdjoints(tape, r.velocity_a, -dv_bar);
    }
    const Vec3<double> d_bar = (n_bar - r.n * r.n.dot(n_bar)) * r.inverse_length + length_bar * r.n;
    AddAdjoints(tape, r.position_b, d_bar);
    AddAdjoints(tape, r.position_a, -d_bar);
    tape->AddAdjoint(r.length, -c_bar);
  }
}

}  // namespace

ConstraintRow<Rev>* RecordedDistanceRows(const Model<Rev>& model, const std::vector<DistancePrimitive<Rev>>& distances,
                                         const BodyFrames<Rev>& frames, const VecX<Rev>& q, const VecX<Rev>& v,
                                         bool velocity_terms, ConstraintRow<Rev>* rows) {
  Tape* tape = ActiveTape();
  const std::shared_ptr<DistanceRecord> record =
      tape ? tape->Reusable<DistanceRecord>() : std::make_shared<DistanceRecord>();
  record->velocity_terms = velocity_terms;
  record->rows.clear();
  record->outputs.clear();
  record->values.clear();
  std::vector<ConstraintRow<Rev>*>& outputs = record->outputs;
  std::vector<double>& values = record->values;
  const Vec3<Rev> still = Zero3<Rev>();
  bool recorded = false;  // a run with nothing recorded (no active tape) gets constants
  for (size_t i = 0; i < distances.size(); ++i) {
    const DistancePrimitive<Rev>& c = distances[i];
    if (!BetweenParticles(model, c)) {
      internal::EvaluateDistanceRow(model, frames, c, q, v, velocity_terms, rows + i);
      continue;
    }
    DistanceRow& r = record->rows.emplace_back();
    const int qa = c.a.body == kWorld ? 0 : model.bodies[c.a.body].q_offset;
    const int qb = c.b.body == kWorld ? 0 : model.bodies[c.b.body].q_offset;
    const Vec3<double> pa = Gather(model, c.a.body, q, qa, c.a.local, &r.position_a);
    const Vec3<double> pb = Gather(model, c.b.body, q, qb, c.b.local, &r.position_b);
    const Vec3<double> d = pb - pa;
    const double length = std::sqrt(d.squaredNorm());
    r.inverse_length = 1.0 / length;
    r.n = d * r.inverse_length;
    r.length = c.length.index;
    double bias = 0.0;
    r.velocity_a.fill(-1);
    r.velocity_b.fill(-1);
    if (velocity_terms) {
      const int va = c.a.body == kWorld ? 0 : model.bodies[c.a.body].v_offset;
      const int vb = c.b.body == kWorld ? 0 : model.bodies[c.b.body].v_offset;
      const Vec3<double> velocity_a = Gather(model, c.a.body, v, va, still, &r.velocity_a);
      const Vec3<double> velocity_b = Gather(model, c.b.body, v, vb, still, &r.velocity_b);
      r.dv = velocity_b - velocity_a;
      r.along = r.n.dot(r.dv);
      r.s = r.dv.squaredNorm() - r.along * r.along;
      bias = r.s * r.inverse_length + r.n.dot(Vec3<double>::Zero());
    }
    ConstraintRow<Rev>* row = rows + i;
    row->a.body = c.a.body;
    row->b.body = c.b.body;
    row->a.rotation = row->b.rotation = Zero3<Rev>();
    outputs.push_back(row);
    values.insert(values.end(), {length - c.length.a, bias, -r.n[0], -r.n[1], -r.n[2], r.n[0], r.n[1], r.n[2]});
    for (const std::array<int, 3>* nodes : {&r.position_a, &r.position_b, &r.velocity_a, &r.velocity_b}) {
      recorded = recorded || (*nodes)[0] >= 0 || (*nodes)[1] >= 0 || (*nodes)[2] >= 0;
    }
    recorded = recorded || r.length >= 0;
  }
  if (outputs.empty()) return rows + distances.size();

  const int first =
      recorded ? tape->RecordExternal(kOutputs * static_cast<int>(outputs.size()),
                                      [record](const double* adjoint, Tape* t) { record->Backward(adjoint, t); })
               : 0;
  for (size_t i = 0; i < outputs.size(); ++i) {
    ConstraintRow<Rev>* row = outputs[i];
    const double* value = values.data() + kOutputs * i;
    const int node = recorded ? first + kOutputs * static_cast<int>(i) : -1;
    auto output = [node](double x, int k) { return node < 0 ? Rev(x) : Rev(x, node + k); };
    row->value = output(value[0], 0);
    if (velocity_terms) row->bias = output(value[1], 1);
    for (int k = 0; k < 3; ++k) {
      row->a.translation[k] = output(value[2 + k], 2 + k);
      row->b.translation[k] = output(value[5 + k], 5 + k);
    }
  }
  return rows + distances.size();
}

}  // namespace tether
