#include "tether_models.h"

#include "bench_models.h"
#include "humanoid_tree.h"
#include "tether/dynamics/io/scene_reader.h"
#include "tether/dynamics/model/kinematics.h"
#include "tether/importers/import_model.h"

namespace tether::bench {

namespace {

// humanoid_tree.h's tree; the fixed torso is the world frame (body indices shift down by one)
Model<double> Humanoid() {
  Model<double> model;
  model.dimension = 3;
  const std::vector<TreeBody> tree = HumanoidTree();
  for (size_t k = 1; k < tree.size(); ++k) {
    AddRigidBody3d<double>(&model, tree[k].name, tree[k].mass, tree[k].inertia.asDiagonal(), tree[k].centre,
                           Vec4<double>(1, 0, 0, 0), Vec3<double>::Zero(), Vec3<double>::Zero());
  }
  for (size_t k = 1; k < tree.size(); ++k) {
    const TreeBody& b = tree[k];
    Joint<double> joint;
    joint.scene_index = model.NumConstraints();
    const bool on_torso = b.parent == 0;
    joint.a = {on_torso ? kWorld : b.parent - 1, on_torso ? b.anchor : Vec3<double>(b.anchor - tree[b.parent].centre)};
    joint.b = {static_cast<int>(k) - 1, b.anchor - b.centre};
    auto universal = [&joint](const Vec3<double>& first, const Vec3<double>& second) {
      joint.type = JointType::kUniversal;
      joint.axis = first;
      joint.axis_b = second;
    };
    switch (b.joint) {
      case TreeJoint::kFixed:
        continue;
      case TreeJoint::kHingeX:
      case TreeJoint::kHingeY:
        joint.type = JointType::kHinge;
        joint.axis = b.joint == TreeJoint::kHingeX ? Vec3<double>::UnitX() : Vec3<double>::UnitY();
        break;
      case TreeJoint::kBall:
        joint.type = JointType::kPin;
        break;
      case TreeJoint::kUniversalZY:
        universal(Vec3<double>::UnitZ(), Vec3<double>::UnitY());
        break;
      case TreeJoint::kUniversalYX:
        universal(Vec3<double>::UnitY(), Vec3<double>::UnitX());
        break;
      case TreeJoint::kUniversalXY:
        universal(Vec3<double>::UnitX(), Vec3<double>::UnitY());
        break;
    }
    AddJoint(&model, joint);
  }
  model.gravity.push_back({0, Vec3<double>(0, 0, -9.81)});
  return model;
}

// MuJoCo's humanoid.xml, imported hanging by its torso, without joint ranges.
Model<double> HumanoidFile() {
  importers::ImportOptions options;
  options.fixed_bodies = {"torso"};
  options.contact = false;
  nlohmann::ordered_json scene = importers::ImportModel(kMujocoHumanoidFile, options).scene;
  for (auto& constraint : scene["constraints"]) constraint.erase("range");
  return ParseScene(nlohmann::json::parse(scene.dump()), kMujocoHumanoidFile).model;
}

}  // namespace

Model<double> TetherPeerScene(Mechanism mechanism, int n, bool rk4, double duration) {
  const Integrator integrator = rk4 ? Integrator::kRk4 : Integrator::kSymplecticEuler;
  Model<double> model;
  switch (mechanism) {
    case Mechanism::kChain:
      model = HorizontalChain(n, integrator, KktSolver::kAuto, 3);
      break;
    case Mechanism::kFourBar:
      model = FourBar(n, KktSolver::kAuto);
      break;
    case Mechanism::kHingeChain:
      model = HingeChain(n, integrator, KktSolver::kAuto);
      break;
    case Mechanism::kHumanoid:
      model = Humanoid();
      break;
    case Mechanism::kHumanoidFile:
      model = HumanoidFile();
      break;
    case Mechanism::kRssr:
      model = ReadSceneFile(TETHER_SOURCE_DIR "/scenes/rssr.json").model;
      break;
  }
  model.simulation.integrator = integrator;
  model.simulation.step = kPeerStep;
  model.simulation.duration = duration;
  SetGains(&model, 100.0, 2500.0);
  return model;
}

double GravityPotential(const Model<double>& model, const VecX<double>& q) {
  double potential = 0.0;
  for (const GravityEffect<double>& g : model.gravity) {
    for (const Body<double>& body : model.bodies) {
      potential -= body.mass * g.acceleration.dot(Translation(model.dimension, q.data() + body.q_offset));
    }
  }
  return potential;
}

}  // namespace tether::bench
