// The hand-written adjoints behind the seam (adjoint/recorded.h) against the templated code they stand for: each
// kernel run in Rev (which takes the recorded operation and its written-out adjoint) and in Jets (which take the
// templated code) on random states of scenes that reach every path, the same values, and the Rev sweep's
// adjoint x_bar = J^T w equal to the Jets' Jacobian J applied to a random output weight w.
//   frames        UpdateFrames                     (frames_adjoint.cc)
//   integrate     Integrate, DexpInv               (configuration_adjoint.cc)
//   rows          EvaluateConstraintRows: distance, point and angle rows (distance_adjoint.cc, rigid_rows_adjoint.cc)
//   forces        AccumulateForces: gyroscopic torques, a 3D joint's angle torque (gyroscopic_adjoint.cc,
//                 joint_torque_adjoint.cc)
//   acceleration  ComputeAcceleration: all of them and the KKT solve (kkt_adjoint.cc)
#include <gtest/gtest.h>

#include <memory>
#include <random>

#include "test_scenes.h"
#include "tether/autodiff/seeds.h"
#include "tether/dynamics/constraints/constraint_rows.h"
#include "tether/dynamics/effects/effects.h"
#include "tether/dynamics/model/configuration_space.h"
#include "tether/dynamics/solvers/constrained_dynamics.h"

namespace tether {
namespace {

// 3D: a body with a full inertia tensor hinged to the world and driven by a motor and a saturated servo, a second on a
// universal joint, a particle on a rod from it and a second particle on a rod from the first; gravity, a spring,
// damping.
const char* kSpatial = R"({"dimension": 3,
  "bodies": [{"name": "a", "type": "rigid", "mass": 2.0, "inertia": [[0.03, 0.004, 0.002], [0.004, 0.04, 0.003],
              [0.002, 0.003, 0.05]], "position": [0.0, 0.0, -0.5]},
             {"name": "b", "type": "rigid", "mass": 1.0, "inertia": [0.01, 0.02, 0.025], "position": [0.0, 0.0, -1.5]},
             {"name": "p", "type": "particle", "mass": 0.5, "position": [0.5, 0.0, -2.0]},
             {"name": "r", "type": "particle", "mass": 0.3, "position": [1.0, 0.0, -2.0]}],
  "constraints": [{"type": "hinge", "name": "shoulder", "bodies": ["world", "a"], "points": [[0.0, 0.0, 0.0],
                   [0.0, 0.0, 0.5]], "axis": [0.0, 1.0, 0.0]},
                  {"type": "universal", "bodies": ["a", "b"], "points": [[0.0, 0.0, -0.5], [0.0, 0.0, 0.5]],
                   "axes": [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]},
                  {"type": "distance", "bodies": ["b", "p"], "points": [[0.0, 0.0, -0.5], [0.0, 0.0, 0.0]]},
                  {"type": "distance", "bodies": ["p", "r"]}],
  "effects": [{"type": "gravity", "acceleration": [0.0, 0.0, -9.81]},
              {"type": "joint_torque", "joint": "shoulder", "value": 0.7},
              {"type": "joint_servo", "joint": "shoulder", "kp": 4.0, "kd": 0.5, "target_rate": 0.2, "limit": 1.5,
               "schedule": {"times": [0.0, 1.0], "values": [0.1, 0.6]}},
              {"type": "spring", "bodies": ["world", "r"], "points": [[1.0, 0.0, 0.0], [0.0, 0.0, 0.0]],
               "stiffness": 5.0, "rest_length": 1.0},
              {"type": "damping", "coefficient": 0.1, "angular_coefficient": 0.02}]})";

// 2D: two planar rods pinned in a chain, a spring and a servo on the elbow's angle, a particle on a rod from the second
// rod (the node-by-node paths of 2D rows).
const char* kPlanar = R"({"dimension": 2,
  "bodies": [{"name": "a", "type": "rigid", "mass": 1.0, "inertia": 0.08, "position": [0.5, 0.0]},
             {"name": "b", "type": "rigid", "mass": 1.0, "inertia": 0.08, "position": [1.5, 0.0]},
             {"name": "p", "type": "particle", "mass": 0.5, "position": [2.5, 0.0]}],
  "constraints": [{"type": "pin", "bodies": ["world", "a"], "points": [[0.0, 0.0], [-0.5, 0.0]]},
                  {"type": "pin", "name": "elbow", "bodies": ["a", "b"], "points": [[0.5, 0.0], [-0.5, 0.0]]},
                  {"type": "distance", "bodies": ["b", "p"], "points": [[0.5, 0.0], [0.0, 0.0]]}],
  "effects": [{"type": "gravity", "acceleration": [0.0, -9.81]},
              {"type": "joint_spring", "joint": "elbow", "stiffness": 3.0, "damping": 0.2},
              {"type": "joint_servo", "joint": "elbow", "kp": 2.0, "kd": 0.3, "target": 0.4},
              {"type": "damping", "coefficient": 0.1, "angular_coefficient": 0.02}]})";

Model<double> Scene(const char* text) { return ParseScene(nlohmann::json::parse(text), "kernels.json").model; }

// A random state near the scene's start, off its constraints: q and v stacked, each quaternion of unit norm.
Eigen::VectorXd RandomState(const Model<double>& model, std::mt19937_64* random) {
  std::normal_distribution<double> normal(0.0, 0.3);
  const State<double> start = InitialState(model);
  Eigen::VectorXd x(start.q.size() + start.v.size());
  for (int i = 0; i < start.q.size(); ++i) x[i] = start.q[i] + 0.2 * normal(*random);
  for (const Body<double>& body : model.bodies) {
    if (body.kind == BodyKind::kRigid3d) x.segment<4>(body.q_offset + 3).normalize();
  }
  for (int i = 0; i < start.v.size(); ++i) x[start.q.size() + i] = normal(*random) * 3.0;
  return x;
}

// kernel(model in T, x in T) -> outputs in T, evaluated in Jets (the templated code) and in Rev (the recorded
// operations): the values agree, and the adjoint of a random weight on the outputs is J^T w.
template <typename Kernel>
void ExpectRecordedEqualsJets(const Model<double>& model, const Eigen::VectorXd& x, Kernel kernel,
                              const std::string& name) {
  const int n = static_cast<int>(x.size());
  Eigen::VectorXd values;
  Eigen::MatrixXd jacobian;
  const Model<Jet> jets = CastModel<Jet>(model);
  for (int first = 0; first < n; first += kJetStride) {
    VecX<Jet> seeded(n);
    for (int i = 0; i < n; ++i) seeded[i] = SeededJet(x[i], i >= first && i < first + kJetStride ? i - first : -1);
    const VecX<Jet> y = kernel(jets, seeded);
    if (first == 0) {
      values.resize(y.size());
      for (int i = 0; i < y.size(); ++i) values[i] = y[i].a;
      jacobian.resize(y.size(), n);
    }
    for (int k = 0; k < kJetStride && first + k < n; ++k) {
      for (int i = 0; i < y.size(); ++i) jacobian(i, first + k) = y[i].v[k];
    }
  }
  std::mt19937_64 random(7);
  std::normal_distribution<double> normal;
  const Eigen::VectorXd weight = Eigen::VectorXd::NullaryExpr(values.size(), [&] { return normal(random); });
  Eigen::VectorXd adjoint(n);
  {
    Tape tape;
    const Model<Rev> revs = CastModel<Rev>(model);
    VecX<Rev> inputs(n);
    for (int i = 0; i < n; ++i) inputs[i] = tape.Variable(x[i]);
    const VecX<Rev> y = kernel(revs, inputs);
    ASSERT_EQ(y.size(), values.size()) << name;
    for (int i = 0; i < y.size(); ++i) {
      EXPECT_NEAR(y[i].a, values[i], 1e-12 * (1.0 + std::abs(values[i]))) << name << ": output " << i;
      tape.AddAdjoint(y[i], weight[i]);
    }
    tape.Backward(0);
    for (int i = 0; i < n; ++i) adjoint[i] = tape.Adjoint(inputs[i]);
  }
  const Eigen::VectorXd expected = jacobian.transpose() * weight;
  EXPECT_GT(expected.norm(), 0.0) << name;
  for (int i = 0; i < n; ++i) {
    EXPECT_NEAR(adjoint[i], expected[i], 1e-9 * (1.0 + expected.cwiseAbs().maxCoeff())) << name << ": input " << i;
  }
}

// The state's q and v in T.
template <typename T>
std::pair<VecX<T>, VecX<T>> Split(const Model<T>& model, const VecX<T>& x) {
  const int nq = model.NumCoordinates(), nv = model.NumVelocities();
  return {x.head(nq), x.segment(nq, nv)};
}

template <typename T>
VecX<T> Stack(const std::vector<T>& values) {
  return Eigen::Map<const VecX<T>>(values.data(), static_cast<Eigen::Index>(values.size()));
}

struct Frames {
  template <typename T>
  VecX<T> operator()(const Model<T>& model, const VecX<T>& x) const {
    const auto [q, v] = Split(model, x);
    BodyFrames<T> frames;
    UpdateFrames(model, q, v, true, &frames);
    std::vector<T> out;
    for (int i : model.rigid_bodies) {
      for (int k = 0; k < 9; ++k) out.push_back(frames[i].R_WB(k));
      for (int k = 0; k < 9; ++k) out.push_back(frames[i].R_WP(k));
      for (int k = 0; k < 3; ++k) out.push_back(frames[i].w_W[k]);
    }
    return Stack(out);
  }
};

struct IntegrateAndDexpInv {
  template <typename T>
  VecX<T> operator()(const Model<T>& model, const VecX<T>& x) const {
    const auto [q, v] = Split(model, x);
    VecX<T> moved(q.size()), rate(v.size());
    Integrate(model, q, v, 0.05, &moved);
    DexpInv(model, VecX<T>(T(0.05) * v), v, &rate);
    VecX<T> out(moved.size() + rate.size());
    out << moved, rate;
    return out;
  }
};

struct Rows {
  template <typename T>
  VecX<T> operator()(const Model<T>& model, const VecX<T>& x) const {
    const auto [q, v] = Split(model, x);
    BodyFrames<T> frames;
    UpdateFrames(model, q, v, true, &frames);
    const ConstraintSet<T> set = BuildConstraintSet(model, InitialState(model).q);
    std::vector<ConstraintRow<T>> rows(DescribeRows(model, set).size());
    EvaluateConstraintRows(model, set, frames, q, v, true, &rows);
    std::vector<T> out;
    for (const ConstraintRow<T>& row : rows) {
      out.push_back(row.value);
      out.push_back(row.bias);
      for (const BodyVector<T>* g : {&row.a, &row.b}) {
        for (int k = 0; k < 3; ++k) out.push_back(g->translation[k]);
        for (int k = 0; k < 3; ++k) out.push_back(g->rotation[k]);
      }
    }
    return Stack(out);
  }
};

struct Forces {
  template <typename T>
  VecX<T> operator()(const Model<T>& model, const VecX<T>& x) const {
    const auto [q, v] = Split(model, x);
    BodyFrames<T> frames;
    UpdateFrames(model, q, v, true, &frames);
    const JointCoordinates<T> coordinates = BuildJointCoordinates(model, InitialState(model).q);
    VecX<T> f = VecX<T>::Constant(v.size(), T(0.0));
    AccumulateForces(model, coordinates, PrincipalInertias(model), frames, 0.0, q, v, &f);
    return f;
  }
};

struct Acceleration {
  template <typename T>
  VecX<T> operator()(const Model<T>& model, const VecX<T>& x) const {
    const auto [q, v] = Split(model, x);
    const VecX<T> start = InitialState(model).q;
    const auto ws = std::make_shared<Workspace<T>>(model, start);
    ws->coordinates = BuildJointCoordinates(model, start);
    workspace = ws;  // the recorded KKT solve's adjoint uses its factorization when the tape is swept
    VecX<T> a(v.size());
    EXPECT_TRUE(ComputeAcceleration(model, 0.0, q, v, ws.get(), &a));
    return a;
  }
  mutable std::shared_ptr<void> workspace;
};

class RecordedKernels : public ::testing::TestWithParam<const char*> {};

TEST_P(RecordedKernels, EqualTheTemplatedCodeInValueAndAdjoint_OnRandomStates) {
  const Model<double> model = Scene(GetParam());
  std::mt19937_64 random(2026);
  for (int trial = 0; trial < 3; ++trial) {
    const Eigen::VectorXd x = RandomState(model, &random);
    ExpectRecordedEqualsJets(model, x, Frames{}, "frames");
    ExpectRecordedEqualsJets(model, x, IntegrateAndDexpInv{}, "integrate");
    ExpectRecordedEqualsJets(model, x, Rows{}, "rows");
    ExpectRecordedEqualsJets(model, x, Forces{}, "forces");
    ExpectRecordedEqualsJets(model, x, Acceleration{}, "acceleration");
  }
}

INSTANTIATE_TEST_SUITE_P(SpatialAndPlanar, RecordedKernels, ::testing::Values(kSpatial, kPlanar));

}  // namespace
}  // namespace tether
