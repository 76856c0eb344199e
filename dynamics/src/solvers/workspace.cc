#include "tether/dynamics/solvers/workspace.h"

#include <Eigen/LU>  // 3 x 3 inverses
#include <algorithm>

#include "tether/dynamics/effects/effects.h"

namespace tether {

template <typename T>
InverseMass<T> BuildInverseMass(const Model<T>& model) {
  InverseMass<T> inverse;
  inverse.diagonal.setZero(model.NumVelocities());
  inverse.rotational.assign(model.bodies.size(), Mat3<T>::Zero());
  for (size_t i = 0; i < model.bodies.size(); ++i) {
    const Body<T>& body = model.bodies[i];
    for (int k = 0; k < model.dimension; ++k) inverse.diagonal[body.v_offset + k] = T(1.0) / body.mass;
    if (body.kind == BodyKind::kPlanar) inverse.diagonal[body.v_offset + 2] = T(1.0) / body.inertia;
    if (body.kind == BodyKind::kRigid3d) inverse.rotational[i] = PrincipalInertia(body).inverse();
  }
  return inverse;
}

template <typename T>
KktSystem<T>::KktSystem(const SchurPattern& pattern, int nv)
    : schur(pattern.nonzeros(), T(0.0)),
      assembly_scratch(12 * static_cast<size_t>(pattern.largest_dense_count()), T(0.0)),
      rhs(VecX<T>::Zero(pattern.size())),
      lambda(VecX<T>::Zero(pattern.size())),
      u_plus_alpha_v(VecX<T>::Zero(nv)) {}

template <typename S, typename T>
TETHER_FLATTEN void ApplyInverseMass(const Model<S>& model, const InverseMass<T>& inverse, const VecX<T>& x,
                                     VecX<T>* out) {
  if (model.spatial_bodies.empty()) {  // M is diagonal
    out->noalias() = inverse.diagonal.cwiseProduct(x);
    return;
  }
  for (size_t i = 0; i < model.bodies.size(); ++i) {
    const Body<S>& body = model.bodies[i];
    if (body.kind != BodyKind::kRigid3d) {
      for (int k = 0; k < body.v_size; ++k)
        (*out)[body.v_offset + k] = inverse.diagonal[body.v_offset + k] * x[body.v_offset + k];
      continue;
    }
    for (int k = 0; k < 3; ++k) (*out)[body.v_offset + k] = inverse.diagonal[body.v_offset + k] * x[body.v_offset + k];
    const Vec3<T> rotation = inverse.rotational[i] * x.template segment<3>(body.v_offset + 3);
    out->template segment<3>(body.v_offset + 3) = rotation;
  }
}

namespace {

SchurShapes FirstShape(const std::vector<RowInfo>& infos, const std::vector<BodyLayout>& layout,
                       const std::vector<int>& double_hinges, KktSolver kind, bool factor_jets) {
  SchurShapes shapes;
  shapes.emplace_back(std::vector<int>{},
                      std::make_unique<SchurShape>(infos, layout, double_hinges, kind, factor_jets));
  return shapes;
}

}  // namespace

template <typename T>
Workspace<T>::Workspace(const Model<T>& model, const VecX<T>& q_start, bool factor_jet_matrices)
    : constraints(BuildConstraintSet(model, q_start)),
      infos(DescribeRows(model, constraints)),
      layout(LayoutOf(model)),
      factor_jet_matrices(factor_jet_matrices),
      shapes(
          FirstShape(infos, layout, DoubleHingesByScene(model.joints), model.simulation.solver, factor_jet_matrices)),
      pattern(&shapes[0].second->pattern),
      solver(&shapes[0].second->solver),
      tree(shapes[0].second->tree ? &*shapes[0].second->tree : nullptr),
      inverse_mass(BuildInverseMass(model)),
      principal_inertia(PrincipalInertias(model)),
      rows(infos.size()),
      kkt(*pattern, model.NumVelocities()) {
  const int nq = model.NumCoordinates(), nv = model.NumVelocities();
  frames.resize(model.bodies.size());
  force.setZero(nv);
  reaction.setZero(nv);
  projection_q.setZero(nq);
  coordinates = BuildJointCoordinates(model, q_start);  // the effects on joint angles read them at every evaluation
}

template <typename T>
void Workspace<T>::SetActiveGaps(const Model<T>& model, const std::vector<LimitPrimitive<T>>& limits,
                                 const std::vector<ContactPrimitive>& contacts, const std::vector<int>& key) {
  constraints.limits = limits;
  constraints.contacts = contacts;
  infos = DescribeRows(model, constraints);
  auto shape = std::find_if(shapes.begin(), shapes.end(), [&key](const auto& s) { return s.first == key; });
  if (shape == shapes.end()) {
    shapes.emplace_back(key, std::make_unique<SchurShape>(infos, layout, DoubleHingesByScene(model.joints),
                                                          model.simulation.solver, factor_jet_matrices));
    shape = shapes.end() - 1;
  }
  pattern = &shape->second->pattern;
  solver = &shape->second->solver;
  tree = shape->second->tree ? &*shape->second->tree : nullptr;
  rows.assign(infos.size(), ConstraintRow<T>());
  kkt = KktSystem<T>(*pattern, model.NumVelocities());
}

template <typename T>
void AssembleSchur(Workspace<T>* ws) {
  AssembleSchur(ws->layout, *ws->pattern, ws->rows, ws->inverse_mass.diagonal, ws->inverse_mass.rotational,
                &ws->kkt.assembly_scratch, &ws->kkt.schur);
}

template <typename T>
void MultiplyJacobian(const Model<T>& model, const VecX<T>& x, Workspace<T>* ws) {
  for (size_t i = 0; i < ws->rows.size(); ++i) {
    ws->kkt.rhs[i] = Dot(model, ws->rows[i].a, x) + Dot(model, ws->rows[i].b, x);
  }
}

template <typename T>
void ApplyReaction(const Model<T>& model, Workspace<T>* ws, VecX<T>* out) {
  out->setZero();
  for (size_t i = 0; i < ws->rows.size(); ++i) {
    AddScaled(model, ws->rows[i].a, ws->kkt.lambda[i], out);
    AddScaled(model, ws->rows[i].b, ws->kkt.lambda[i], out);
  }
  ApplyInverseMass(model, ws->inverse_mass, *out, out);
}

template <typename T>
void EvaluateRows(const Model<T>& model, const VecX<T>& q, const VecX<T>& v, bool velocity_terms, Workspace<T>* ws) {
  UpdateFrames(model, q, v, velocity_terms, &ws->frames);
  EvaluateConstraintRows(model, ws->constraints, ws->frames, q, v, velocity_terms, &ws->rows);
}

#define TETHER_INSTANTIATE_WORKSPACE(T)                                                                   \
  template struct Workspace<T>;                                                                           \
  template InverseMass<T> BuildInverseMass<T>(const Model<T>&);                                           \
  template struct KktSystem<T>;                                                                           \
  template void ApplyInverseMass<T, T>(const Model<T>&, const InverseMass<T>&, const VecX<T>&, VecX<T>*); \
  template void EvaluateRows<T>(const Model<T>&, const VecX<T>&, const VecX<T>&, bool, Workspace<T>*);    \
  template void MultiplyJacobian<T>(const Model<T>&, const VecX<T>&, Workspace<T>*);                      \
  template void ApplyReaction<T>(const Model<T>&, Workspace<T>*, VecX<T>*);                               \
  template void AssembleSchur<T>(Workspace<T>*);
TETHER_FOR_EACH_SCALAR(TETHER_INSTANTIATE_WORKSPACE)
// the recorded KKT solve's values in double (kkt_adjoint.cc)
template void ApplyInverseMass<Rev, double>(const Model<Rev>&, const InverseMass<double>&, const VecX<double>&,
                                            VecX<double>*);

}  // namespace tether
