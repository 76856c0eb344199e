// The KKT solve of one evaluation recorded as one operation (constrained_dynamics.h), and its adjoint.
//
// Forward, in double, what KktAcceleration computes for a double run (the same code: the same values):
//   u = M^-1 f,  w = u + alpha v,  rhs_i = J_i w + bias_i + beta C_i,  S lambda = rhs,  S = J M^-1 J^T,
//   y = f - J^T lambda,  a = M^-1 y.
// Backward, from abar, in double, with one more solve by the forward factorization, kept (S is symmetric):
//   g = M^-1 abar,  lambdabar = -J g,  rbar = S^-1 lambdabar,  JTr = J^T rbar,  h = g + M^-1 JTr,
//   fbar      += h
//   vbar      += alpha JTr,   alphabar += JTr . v,   betabar += rbar . C
//   biasbar_i += rbar_i,      Cbar_i += beta rbar_i
//   Jbar_i    += rbar_i (a + alpha v) - lambda_i h                    (on row i's bodies)
//   (M^-1)bar += abar y^T + JTr f^T    where M^-1 multiplies (ApplyInverseMass)
//                - JTr (J^T lambda)^T  where S is assembled (AssembleSchur: the translations of a body share
//                                      one inverse mass there)
// by the chain rule through each line of the forward computation: a solve's adjoint is rbar = S^-1 lambdabar
// with Sbar = -rbar lambda^T, which reaches J and M^-1 through S = J M^-1 J^T (and M^-1 J^T lambda = u - a).
// Where the solver regularized S (S + eps (diag S + floor), the floor a constant, schur_system.h), Sbar's
// diagonal also counts eps times more:
//   Jbar_i += -2 eps rbar_i lambda_i M^-1 J_i,   (M^-1)bar += -eps rbar_i lambda_i J_i J_i^T.
// The rows, forces and inverse mass stay recorded, and carry these adjoints on to q, v and the parameters.
#include <array>
#include <memory>
#include <optional>

#include "tether/dynamics/constrained_dynamics.h"
#include "tether/dynamics/recorded_blocks.h"

namespace tether {
namespace {

// A Jacobian block's six components (translation, then rotation), as values or as nodes.
BodyVector<double> Values(const BodyVector<Rev>& g) {
  BodyVector<double> out;
  out.body = g.body;
  for (int k = 0; k < 3; ++k) {
    out.translation[k] = g.translation[k].a;
    out.rotation[k] = g.rotation[k].a;
  }
  return out;
}
std::array<int, 6> Nodes(const BodyVector<Rev>& g) {
  return {g.translation[0].index, g.translation[1].index, g.translation[2].index,
          g.rotation[0].index,    g.rotation[1].index,    g.rotation[2].index};
}
void AddAdjoints(Tape* tape, const std::array<int, 6>& nodes, const BodyVector<double>& adjoint) {
  for (int k = 0; k < 3; ++k) {
    tape->AddAdjoint(nodes[k], adjoint.translation[k]);
    tape->AddAdjoint(nodes[3 + k], adjoint.rotation[k]);
  }
}

// What the backward sweep needs of one evaluation: the forward values, and the nodes they came from.
struct KktRecord {
  const Model<Rev>* model;  // the bodies' layout
  SchurSolver* solver;       // solves with the forward factorization in the backward sweep
  std::vector<ConstraintRow<double>> rows;
  std::vector<std::array<int, 2>> row_nodes;                   // value, bias
  std::vector<std::array<std::array<int, 6>, 2>> block_nodes;  // J_i on its first and second body
  InverseMass<double> inverse_mass;
  VecX<int> diagonal_nodes;
  std::vector<Mat3<int>> rotational_nodes;
  std::optional<KktSystem<double>> system;  // the solve's S and multipliers lambda
  VecX<double> f, v, y, a;
  VecX<int> f_nodes, v_nodes;
  double alpha = 0.0, beta = 0.0;
  int alpha_node = -1, beta_node = -1;
  SchurSolver::Factorization factorization;  // of S as solved forward: regularized or not
  bool regularized = false;
  struct {
    VecX<double> g, r_bar, jt_r, jt_lambda, h, a_plus_alpha_v;
  } scratch;  // the backward sweep's vectors, allocated once per reused record

  void Backward(const double* a_bar_data, Tape* tape);
};

// (M^-1)bar from out = M^-1 x with outbar: the diagonal's entries and the 3D bodies' blocks, by body.
void AddInverseMassAdjoint(const KktRecord& r, const VecX<double>& out_bar, const VecX<double>& x, Tape* tape) {
  for (size_t i = 0; i < r.model->bodies.size(); ++i) {
    const Body<Rev>& body = r.model->bodies[i];
    const bool spatial = body.kind == BodyKind::kRigid3d;
    const int diagonal = spatial ? 3 : body.v_size;
    for (int k = 0; k < diagonal; ++k) {
      tape->AddAdjoint(r.diagonal_nodes[body.v_offset + k], out_bar[body.v_offset + k] * x[body.v_offset + k]);
    }
    if (!spatial) continue;
    const Mat3<double> outer = out_bar.segment<3>(body.v_offset + 3) * x.segment<3>(body.v_offset + 3).transpose();
    for (int c = 0; c < 3; ++c) {
      for (int k = 0; k < 3; ++k) tape->AddAdjoint(r.rotational_nodes[i](k, c), outer(k, c));
    }
  }
}

// (M^-1)bar from S = J M^-1 J^T with Sbar = -s t^T summed over pairs (s, t) of generalized vectors that stand
// for J^T of multiplier-shaped vectors, as AssembleSchur uses M^-1: a body's translations share one entry.
void AddAssemblyAdjoint(const KktRecord& r, double scale, const VecX<double>& s, const VecX<double>& t, Tape* tape) {
  for (size_t i = 0; i < r.model->bodies.size(); ++i) {
    const Body<Rev>& body = r.model->bodies[i];
    const int o = body.v_offset;
    const int translations = body.kind == BodyKind::kParticle ? body.v_size : body.kind == BodyKind::kPlanar ? 2 : 3;
    double shared = 0.0;
    for (int k = 0; k < translations; ++k) shared += s[o + k] * t[o + k];
    tape->AddAdjoint(r.diagonal_nodes[o], scale * shared);
    if (body.kind == BodyKind::kPlanar) tape->AddAdjoint(r.diagonal_nodes[o + 2], scale * s[o + 2] * t[o + 2]);
    if (body.kind != BodyKind::kRigid3d) continue;
    const Mat3<double> outer = s.segment<3>(o + 3) * t.segment<3>(o + 3).transpose();
    for (int c = 0; c < 3; ++c) {
      for (int k = 0; k < 3; ++k) tape->AddAdjoint(r.rotational_nodes[i](k, c), scale * outer(k, c));
    }
  }
}

void KktRecord::Backward(const double* a_bar_data, Tape* tape) {
  const Model<Rev>& m = *model;
  const int nv = static_cast<int>(f.size()), rows_count = static_cast<int>(rows.size());
  const Eigen::Map<const VecX<double>> a_bar(a_bar_data, nv);
  const VecX<double>& lambda = system->lambda;
  auto& [g, r_bar, jt_r, jt_lambda, h, a_plus_alpha_v] = scratch;
  h = a_bar;
  g.resize(nv);
  ApplyInverseMass(m, inverse_mass, h, &g);
  r_bar.resize(rows_count);
  for (int i = 0; i < rows_count; ++i) r_bar[i] = -(Dot(m, rows[i].a, g) + Dot(m, rows[i].b, g));  // lambdabar
  solver->SolveWith(factorization, &r_bar);
  jt_r.setZero(nv);
  jt_lambda.setZero(nv);
  for (int i = 0; i < rows_count; ++i) {
    AddScaled(m, rows[i].a, r_bar[i], &jt_r);
    AddScaled(m, rows[i].b, r_bar[i], &jt_r);
    AddScaled(m, rows[i].a, lambda[i], &jt_lambda);
    AddScaled(m, rows[i].b, lambda[i], &jt_lambda);
  }
  ApplyInverseMass(m, inverse_mass, jt_r, &h);
  h += g;
  a_plus_alpha_v = a + alpha * v;

  for (int i = 0; i < nv; ++i) {
    tape->AddAdjoint(f_nodes[i], h[i]);
    tape->AddAdjoint(v_nodes[i], alpha * jt_r[i]);
  }
  tape->AddAdjoint(alpha_node, jt_r.dot(v));
  double beta_bar = 0.0;
  for (int i = 0; i < rows_count; ++i) {
    beta_bar += r_bar[i] * rows[i].value;
    tape->AddAdjoint(row_nodes[i][0], beta * r_bar[i]);
    tape->AddAdjoint(row_nodes[i][1], r_bar[i]);
    const std::array<const BodyVector<double>*, 2> blocks{&rows[i].a, &rows[i].b};
    for (int side = 0; side < 2; ++side) {
      const BodyVector<double>& block = *blocks[side];
      if (block.body == kWorld) continue;
      BodyVector<double> adjoint = Slice(m, block.body, a_plus_alpha_v);
      const BodyVector<double> along_h = Slice(m, block.body, h);
      adjoint.translation = r_bar[i] * adjoint.translation - lambda[i] * along_h.translation;
      adjoint.rotation = r_bar[i] * adjoint.rotation - lambda[i] * along_h.rotation;
      if (regularized) {  // -2 eps rbar_i lambda_i M^-1 J_i, and the matching (M^-1)bar
        const double d = -kSchurRegularization * r_bar[i] * lambda[i];
        VecX<double> block_vector = VecX<double>::Zero(nv), weighted(nv);
        AddScaled(m, block, 1.0, &block_vector);
        ApplyInverseMass(m, inverse_mass, block_vector, &weighted);
        const BodyVector<double> scaled = Slice(m, block.body, weighted);
        adjoint.translation += 2.0 * d * scaled.translation;
        adjoint.rotation += 2.0 * d * scaled.rotation;
        AddAssemblyAdjoint(*this, d, block_vector, block_vector, tape);
      }
      AddAdjoints(tape, block_nodes[i][side], adjoint);
    }
  }
  tape->AddAdjoint(beta_node, beta_bar);
  AddInverseMassAdjoint(*this, a_bar, y, tape);
  AddInverseMassAdjoint(*this, jt_r, f, tape);
  AddAssemblyAdjoint(*this, -1.0, jt_r, jt_lambda, tape);
}

}  // namespace

template <>
bool SolveKkt<Rev>(const Model<Rev>& model, const VecX<Rev>& v, Workspace<Rev>* ws, VecX<Rev>* a) {
  Tape* tape = ActiveTape();
  const std::shared_ptr<KktRecord> record = tape ? tape->Reusable<KktRecord>() : std::make_shared<KktRecord>();
  KktRecord& r = *record;
  r.model = &model;
  r.solver = &ws->solver;
  bool recorded = ws->alpha.index >= 0 || ws->beta.index >= 0;
  const size_t m = ws->rows.size();
  r.rows.resize(m);
  r.row_nodes.resize(m);
  r.block_nodes.resize(m);
  for (size_t i = 0; i < m; ++i) {
    const ConstraintRow<Rev>& row = ws->rows[i];
    r.rows[i] = {row.value.a, row.bias.a, Values(row.a), Values(row.b)};
    r.row_nodes[i] = {row.value.index, row.bias.index};
    r.block_nodes[i] = {Nodes(row.a), Nodes(row.b)};
    for (int node : r.row_nodes[i]) recorded = recorded || node >= 0;
    for (const auto& nodes : r.block_nodes[i]) {
      for (int node : nodes) recorded = recorded || node >= 0;
    }
  }
  r.inverse_mass.diagonal = Values(ws->inverse_mass.diagonal);
  r.diagonal_nodes = Nodes(ws->inverse_mass.diagonal);
  const size_t bodies = ws->inverse_mass.rotational.size();
  r.inverse_mass.rotational.resize(bodies);
  r.rotational_nodes.resize(bodies);
  for (size_t b = 0; b < bodies; ++b) {
    r.inverse_mass.rotational[b] = Values(ws->inverse_mass.rotational[b]);
    r.rotational_nodes[b] = Nodes(ws->inverse_mass.rotational[b]);
    recorded = recorded || AnyRecorded(r.rotational_nodes[b]);
  }
  r.f = Values(ws->force);
  r.f_nodes = Nodes(ws->force);
  r.v = Values(v);
  r.v_nodes = Nodes(v);
  recorded = recorded || AnyRecorded(r.f_nodes) || AnyRecorded(r.v_nodes) || AnyRecorded(r.diagonal_nodes);
  r.alpha = ws->alpha.a;
  r.beta = ws->beta.a;
  r.alpha_node = ws->alpha.index;
  r.beta_node = ws->beta.index;

  if (!r.system || r.system->u_plus_alpha_v.size() != r.f.size() ||
      r.system->schur.size() != static_cast<size_t>(ws->pattern.nonzeros())) {
    r.system.emplace(ws->pattern, static_cast<int>(r.f.size()));
  }
  r.y = r.f;
  r.a.resize(r.f.size());
  const bool solved = KktAcceleration(model, ws->layout, ws->pattern, &ws->solver, r.rows, r.inverse_mass, r.v,
                                      r.alpha, r.beta, &r.y, &*r.system, &r.a);
  if (!solved || !recorded) {
    for (int i = 0; i < a->size(); ++i) (*a)[i] = Rev(r.a[i]);
    return solved;
  }
  r.regularized = ws->solver.starts_regularized();
  ws->solver.SaveFactorization(&r.factorization);
  const int first = tape->RecordExternal(
      static_cast<int>(r.a.size()), [record](const double* a_bar, Tape* tape) { record->Backward(a_bar, tape); });
  for (int i = 0; i < a->size(); ++i) (*a)[i] = Rev(r.a[i], first + i);
  return true;
}

}  // namespace tether
