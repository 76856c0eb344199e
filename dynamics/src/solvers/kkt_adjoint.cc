// The KKT solve of one evaluation recorded as one operation (constrained_dynamics.h), and its adjoint.
//
// Forward, in double, what KktAcceleration computes for a double run (the same code: the same values):
//   u = M^-1 f,  w = u + alpha v,  rhs_i = J_i w + bias_i + beta C_i,  S lambda = rhs,  S = J M^-1 J^T,
//   y = f - J^T lambda,  a = M^-1 y;
// where the double run kept this solve (a KKT log, kkt_log.h), its lambda and factorization are taken instead of
// assembling, factoring and solving S again.
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
// J is kept as sparse rows over the velocities (a row's entries on its first body, then on its second, in the
// order of kinematics.h's Dot and AddScaled, so that J^T lambda adds up the same doubles; constant zeros, which
// add nothing, left out), each entry with its node: the sweep walks entries, not bodies.
#include <algorithm>
#include <array>
#include <memory>
#include <optional>
#include <utility>
#include <vector>

#include "tether/dynamics/adjoint/recorded.h"
#include "tether/dynamics/adjoint/recorded_blocks.h"
#include "tether/dynamics/model/errors.h"
#include "tether/dynamics/solvers/constrained_dynamics.h"

namespace tether {
namespace {

// J by rows over the velocity vector: row i's entries are [start[i], start[i + 1]), those on its second body
// from second[i]; an entry is J(i, column) = value, recorded as node (-1: a constant).
struct SparseRows {
  struct Entry {
    int column, node;
    double value;
  };
  std::vector<int> start{0}, second;
  std::vector<Entry> entries;  // [0, start.back()) in use; sized for the most a row can have

  // Empties the rows, with room for `rows` of up to two 3D bodies.
  void Clear(size_t rows) {
    start.assign(1, 0);
    second.clear();
    if (entries.size() < 12 * rows) entries.resize(12 * rows);
  }
  // Appends a row from its two blocks: the components each body kind has (kinematics.h's Dot), but for the
  // constant zeros (a point row's translational part is a unit vector), which add nothing either way.
  void Append(const std::vector<BodyLayout>& layout, int dimension, const BodyVector<Rev>& a,
              const BodyVector<Rev>& b) {
    int used = start.back();
    AppendBlock(layout, dimension, a, &used);
    second.push_back(used);
    AppendBlock(layout, dimension, b, &used);
    start.push_back(used);
  }
  int rows() const { return static_cast<int>(second.size()); }
  double Dot(int i, const VecX<double>& x) const {
    double sum = 0.0;
    for (int e = start[i]; e < start[i + 1]; ++e) sum += entries[e].value * x[entries[e].column];
    return sum;
  }
  // x += scale J_i^T, entry by entry as AddScaled adds a block's components
  void AddTransposed(int i, double scale, VecX<double>* x) const {
    for (int e = start[i]; e < start[i + 1]; ++e) (*x)[entries[e].column] += scale * entries[e].value;
  }

 private:
  void AppendBlock(const std::vector<BodyLayout>& layout, int dimension, const BodyVector<Rev>& g, int* used) {
    if (g.body == kWorld) return;
    const BodyLayout& body = layout[g.body];
    Entry* out = entries.data();
    const auto add = [out, used](int c, const Rev& x) {
      if (x.a != 0.0 || x.index >= 0) out[(*used)++] = {c, x.index, x.a};
    };
    const int o = body.v_offset;
    if (body.kind == BodyKind::kParticle) {
      for (int k = 0; k < dimension; ++k) add(o + k, g.translation[k]);
    } else if (body.kind == BodyKind::kPlanar) {
      add(o, g.translation[0]);
      add(o + 1, g.translation[1]);
      add(o + 2, g.rotation[2]);
    } else {
      for (int k = 0; k < 3; ++k) add(o + k, g.translation[k]);
      for (int k = 0; k < 3; ++k) add(o + 3 + k, g.rotation[k]);
    }
  }
};

// A Jacobian block's values.
BodyVector<double> Values(const BodyVector<Rev>& g) {
  BodyVector<double> out;
  out.body = g.body;
  out.translation = tether::Values(g.translation);
  out.rotation = tether::Values(g.rotation);
  return out;
}

// How many of a body's velocity components M^-1 scales by its diagonal (the rest: a 3D body's rotation block),
// and how many of them are translations, which share one inverse mass where S is assembled.
int DiagonalCount(BodyKind kind, int dimension) { return kind == BodyKind::kParticle ? dimension : 3; }
int TranslationCount(BodyKind kind, int dimension) {
  return kind == BodyKind::kParticle ? dimension : kind == BodyKind::kPlanar ? 2 : 3;
}

// What the backward sweep needs of one evaluation: the forward values, and the nodes they came from.
struct KktRecord {
  const Model<Rev>* model;                // the bodies' layout, for ApplyInverseMass
  const std::vector<BodyLayout>* layout;  // the same, compact
  int dimension = 2;
  SchurSolver* solver;  // solves with the forward factorization in the backward sweep
  SparseRows jacobian;
  VecX<double> constraint;                    // C_i
  std::vector<std::array<int, 2>> row_nodes;  // C_i, bias_i
  std::vector<ConstraintRow<double>> rows;    // the rows in double, where this record solves (no KKT log)
  InverseMass<double> inverse_mass;
  VecX<int> diagonal_nodes;
  std::vector<Mat3<int>> rotational_nodes;
  std::optional<KktSystem<double>> system;       // the solve's S, where this record solves it
  const SchurPattern* system_pattern = nullptr;  // the pattern `system` is sized for
  VecX<double> lambda;                           // the multipliers
  VecX<double> f, v, y, a;
  VecX<int> f_nodes, v_nodes;
  double alpha = 0.0, beta = 0.0;
  int alpha_node = -1, beta_node = -1;
  SchurSolver::Factorization factorization;  // of S as solved forward: regularized or not
  bool regularized = false;
  struct {
    VecX<double> g, r_bar, jt_r, jt_lambda, h, a_plus_alpha_v, block, weighted;
  } scratch;  // the backward sweep's vectors, allocated once per reused record

  void Backward(const double* a_bar_data, Tape* tape);
  void AddRegularizedAdjoint(int first, int end, double d, Tape* tape);
};

// (M^-1)bar from out1 = M^-1 x1 and out2 = M^-1 x2 with out1bar, out2bar: the diagonal's entries and the 3D
// bodies' blocks, by body.
void AddInverseMassAdjoint(const KktRecord& r, const Eigen::Ref<const VecX<double>>& out1_bar, const VecX<double>& x1,
                           const VecX<double>& out2_bar, const VecX<double>& x2, Tape* tape) {
  const std::vector<BodyLayout>& layout = *r.layout;
  for (size_t i = 0; i < layout.size(); ++i) {
    const int o = layout[i].v_offset;
    for (int k = 0; k < DiagonalCount(layout[i].kind, r.dimension); ++k) {
      tape->AddAdjoint(r.diagonal_nodes[o + k], out1_bar[o + k] * x1[o + k] + out2_bar[o + k] * x2[o + k]);
    }
    if (layout[i].kind != BodyKind::kRigid3d) continue;
    const Mat3<double> outer = out1_bar.segment<3>(o + 3) * x1.segment<3>(o + 3).transpose() +
                               out2_bar.segment<3>(o + 3) * x2.segment<3>(o + 3).transpose();
    AddAdjoints(tape, r.rotational_nodes[i], outer);
  }
}

// (M^-1)bar from S = J M^-1 J^T with Sbar = -s t^T summed over pairs (s, t) of generalized vectors that stand
// for J^T of multiplier-shaped vectors, as AssembleSchur uses M^-1: a body's translations share one entry.
void AddAssemblyAdjoint(const KktRecord& r, double scale, const VecX<double>& s, const VecX<double>& t, Tape* tape) {
  const std::vector<BodyLayout>& layout = *r.layout;
  for (size_t i = 0; i < layout.size(); ++i) {
    const BodyKind kind = layout[i].kind;
    const int o = layout[i].v_offset;
    double shared = 0.0;
    for (int k = 0; k < TranslationCount(kind, r.dimension); ++k) shared += s[o + k] * t[o + k];
    tape->AddAdjoint(r.diagonal_nodes[o], scale * shared);
    if (kind == BodyKind::kPlanar) tape->AddAdjoint(r.diagonal_nodes[o + 2], scale * s[o + 2] * t[o + 2]);
    if (kind != BodyKind::kRigid3d) continue;
    const Mat3<double> outer = s.segment<3>(o + 3) * t.segment<3>(o + 3).transpose();
    AddAdjoints(tape, r.rotational_nodes[i], scale * outer);
  }
}

// The regularization's terms for the entries [first, end) of one row on one body, with d = -eps rbar_i lambda_i:
// Jbar += 2 d M^-1 J_i there, and (M^-1)bar += d J_i J_i^T (M^-1 is block diagonal by body).
void KktRecord::AddRegularizedAdjoint(int first, int end, double d, Tape* tape) {
  if (first == end) return;
  auto& [g, r_bar, jt_r, jt_lambda, h, a_plus_alpha_v, block, weighted] = scratch;
  block.setZero(f.size());
  weighted.resize(f.size());
  for (int e = first; e < end; ++e) block[jacobian.entries[e].column] = jacobian.entries[e].value;
  ApplyInverseMass(*model, inverse_mass, block, &weighted);
  for (int e = first; e < end; ++e) {
    tape->AddAdjoint(jacobian.entries[e].node, 2.0 * d * weighted[jacobian.entries[e].column]);
  }
  AddAssemblyAdjoint(*this, d, block, block, tape);
}

void KktRecord::Backward(const double* a_bar_data, Tape* tape) {
  const int nv = static_cast<int>(f.size()), rows_count = jacobian.rows();
  const Eigen::Map<const VecX<double>> a_bar(a_bar_data, nv);
  auto& [g, r_bar, jt_r, jt_lambda, h, a_plus_alpha_v, block, weighted] = scratch;
  h = a_bar;
  g.resize(nv);
  ApplyInverseMass(*model, inverse_mass, h, &g);
  r_bar.resize(rows_count);
  for (int i = 0; i < rows_count; ++i) r_bar[i] = -jacobian.Dot(i, g);  // lambdabar
  solver->SolveWith(factorization, &r_bar);
  jt_r.setZero(nv);
  for (int i = 0; i < rows_count; ++i) jacobian.AddTransposed(i, r_bar[i], &jt_r);
  jt_lambda = f - y;  // y = f - J^T lambda
  ApplyInverseMass(*model, inverse_mass, jt_r, &h);
  h += g;
  a_plus_alpha_v = a + alpha * v;

  for (int i = 0; i < nv; ++i) {
    tape->AddAdjoint(f_nodes[i], h[i]);
    tape->AddAdjoint(v_nodes[i], alpha * jt_r[i]);
  }
  tape->AddAdjoint(alpha_node, jt_r.dot(v));
  tape->AddAdjoint(beta_node, r_bar.dot(constraint));
  for (int i = 0; i < rows_count; ++i) {
    tape->AddAdjoint(row_nodes[i][0], beta * r_bar[i]);
    tape->AddAdjoint(row_nodes[i][1], r_bar[i]);
    for (int e = jacobian.start[i]; e < jacobian.start[i + 1]; ++e) {
      const SparseRows::Entry& entry = jacobian.entries[e];
      tape->AddAdjoint(entry.node, r_bar[i] * a_plus_alpha_v[entry.column] - lambda[i] * h[entry.column]);
    }
    if (regularized) {
      const double d = -kSchurRegularization * r_bar[i] * lambda[i];
      AddRegularizedAdjoint(jacobian.start[i], jacobian.second[i], d, tape);
      AddRegularizedAdjoint(jacobian.second[i], jacobian.start[i + 1], d, tape);
    }
  }
  AddInverseMassAdjoint(*this, a_bar, y, jt_r, f, tape);
  AddAssemblyAdjoint(*this, -1.0, jt_r, jt_lambda, tape);
}

}  // namespace

std::optional<bool> RecordedKktAcceleration(const Model<Rev>& model, const VecX<Rev>& v, Workspace<Rev>* ws,
                                            VecX<Rev>* a) {
  if (!ws->sliding.empty()) {              // sliding friction: solved again operation by operation on the tape
    if (ws->kkt_log) ws->kkt_log->Take();  // the double run's solve of this evaluation, not used
    return std::nullopt;
  }
  Tape* tape = ActiveTape();
  const std::shared_ptr<KktRecord> record = tape ? tape->Reusable<KktRecord>() : std::make_shared<KktRecord>();
  KktRecord& r = *record;
  r.model = &model;
  r.layout = &ws->layout;
  r.dimension = model.dimension;
  r.solver = ws->solver;
  const size_t m = ws->rows.size();
  r.jacobian.Clear(m);
  r.constraint.resize(static_cast<Eigen::Index>(m));
  r.row_nodes.resize(m);
  for (size_t i = 0; i < m; ++i) {
    const ConstraintRow<Rev>& row = ws->rows[i];
    r.jacobian.Append(ws->layout, model.dimension, row.a, row.b);
    r.constraint[static_cast<Eigen::Index>(i)] = row.value.a;
    r.row_nodes[i] = {row.value.index, row.bias.index};
  }
  bool recorded = ws->alpha.index >= 0 || ws->beta.index >= 0 ||
                  std::any_of(r.jacobian.entries.begin(), r.jacobian.entries.begin() + r.jacobian.start.back(),
                              [](const SparseRows::Entry& e) { return e.node >= 0; }) ||
                  std::any_of(r.row_nodes.begin(), r.row_nodes.end(),
                              [](const std::array<int, 2>& nodes) { return nodes[0] >= 0 || nodes[1] >= 0; });
  ValuesInto(ws->inverse_mass.diagonal, &r.inverse_mass.diagonal);
  NodesInto(ws->inverse_mass.diagonal, &r.diagonal_nodes);
  const size_t bodies = ws->inverse_mass.rotational.size();
  r.inverse_mass.rotational.resize(bodies);
  r.rotational_nodes.resize(bodies);
  for (size_t b = 0; b < bodies; ++b) {
    r.inverse_mass.rotational[b] = Values(ws->inverse_mass.rotational[b]);
    r.rotational_nodes[b] = Nodes(ws->inverse_mass.rotational[b]);
    recorded = recorded || AnyRecorded(r.rotational_nodes[b]);
  }
  ValuesInto(ws->force, &r.f);
  NodesInto(ws->force, &r.f_nodes);
  ValuesInto(v, &r.v);
  NodesInto(v, &r.v_nodes);
  recorded = recorded || AnyRecorded(r.f_nodes) || AnyRecorded(r.v_nodes) || AnyRecorded(r.diagonal_nodes);
  r.alpha = ws->alpha.a;
  r.beta = ws->beta.a;
  r.alpha_node = ws->alpha.index;
  r.beta_node = ws->beta.index;

  r.y = r.f;
  r.a.resize(r.f.size());
  bool solved = true;
  if (KktSolve* kept = ws->kkt_log ? ws->kkt_log->Take() : nullptr) {  // the double run solved it: the same S
    r.lambda.swap(kept->lambda);
    r.factorization.sparse.lower.swap(kept->factorization.sparse.lower);
    r.factorization.sparse.inverse_d.swap(kept->factorization.sparse.inverse_d);
    std::swap(r.factorization.dense, kept->factorization.dense);
    r.regularized = kept->regularized;
    ws->solver->RestoreConditioning(kept->regularized, kept->near_singular, kept->close_to_pass);
    for (size_t i = 0; i < m; ++i) r.jacobian.AddTransposed(static_cast<int>(i), -r.lambda[i], &r.y);  // f - J^T lambda
    ApplyInverseMass(model, r.inverse_mass, r.y, &r.a);
  } else {
    r.rows.resize(m);
    for (size_t i = 0; i < m; ++i) {
      const ConstraintRow<Rev>& row = ws->rows[i];
      r.rows[i] = {row.value.a, row.bias.a, Values(row.a), Values(row.b)};
    }
    if (!r.system || r.system_pattern != ws->pattern || r.system->u_plus_alpha_v.size() != r.f.size()) {
      r.system.emplace(*ws->pattern, static_cast<int>(r.f.size()));
      r.system_pattern = ws->pattern;
    }
    solved = KktAcceleration(model, ws->layout, *ws->pattern, ws->solver, r.rows, r.inverse_mass, r.v, r.alpha, r.beta,
                             &r.y, &*r.system, &r.a);
    if (solved && recorded) {
      r.lambda = r.system->lambda;
      r.regularized = ws->solver->starts_regularized();
      ws->solver->SaveFactorization(&r.factorization);
    }
  }
  if (!solved || !recorded) {
    for (int i = 0; i < a->size(); ++i) (*a)[i] = Rev(r.a[i]);
    return solved;
  }
  const int first = tape->RecordExternal(static_cast<int>(r.a.size()),
                                         [record](const double* a_bar, Tape* tape) { record->Backward(a_bar, tape); });
  for (int i = 0; i < a->size(); ++i) (*a)[i] = Rev(r.a[i], first + i);
  return true;
}

}  // namespace tether
