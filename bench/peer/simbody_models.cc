#include "simbody_models.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>

#include "bench_models.h"
#include "humanoid_tree.h"
#include "rssr_linkage.h"

namespace tether::bench {
namespace {

using SimTK::MobilizedBody;
using SimTK::Transform;

SimTK::Vec3 ToSimTK(const Vec3<double>& v) { return SimTK::Vec3(v.x(), v.y(), v.z()); }

// A rigid body of `mass` whose frame is at its centre of mass; `inertia` about the centre, in the body's axes
SimTK::Body::Rigid RigidBody(double mass, const Mat3<double>& inertia) {
  const SimTK::Mat33 i(inertia(0, 0), inertia(0, 1), inertia(0, 2), inertia(1, 0), inertia(1, 1), inertia(1, 2),
                       inertia(2, 0), inertia(2, 1), inertia(2, 2));
  return SimTK::Body::Rigid(SimTK::MassProperties(mass, SimTK::Vec3(0), SimTK::Inertia(i)));
}

// A hinge's frame J in the world: its z along `axis`, at `point`
Transform HingeFrame(const Vec3<double>& axis, const Vec3<double>& point) {
  return Transform(SimTK::Rotation(SimTK::UnitVec3(ToSimTK(axis)), SimTK::ZAxis), ToSimTK(point));
}

// A universal joint's frame: x along the first axis (fixed in the parent), y along the second (fixed in the body)
Transform UniversalFrame(const Vec3<double>& first, const Vec3<double>& second, const Vec3<double>& point) {
  return Transform(SimTK::Rotation(SimTK::UnitVec3(ToSimTK(first)), SimTK::XAxis, ToSimTK(second), SimTK::YAxis),
                   ToSimTK(point));
}

// Adds a body starting at `centre` (axes the world's) to `parent` by the mobilizer M, whose joint frame in the world
// is J; F = X_GP^-1 J on the parent, M = X_GB^-1 J on the body (so X_FM = identity at the start).
template <typename M>
M Attach(MobilizedBody& parent, const Vec3<double>& parent_centre, const SimTK::Body& body, const Vec3<double>& centre,
         const Transform& J) {
  return M(parent, ~Transform(ToSimTK(parent_centre)) * J, body, ~Transform(ToSimTK(centre)) * J);
}

std::vector<MobilizedBody> HingeChain(SimTK::SimbodyMatterSubsystem& matter, int n) {
  const Vec3<double> moments = RodInertia(1.0, 1.0);
  const SimTK::Body::Rigid rod = RigidBody(1.0, moments.asDiagonal());
  std::vector<MobilizedBody> links;
  MobilizedBody parent = matter.Ground();
  Vec3<double> parent_centre = Vec3<double>::Zero();
  for (int k = 0; k < n; ++k) {
    const Vec3<double> centre(k + 0.5, 0, 0);
    links.push_back(Attach<MobilizedBody::Pin>(parent, parent_centre, rod, centre,
                                               HingeFrame(Vec3<double>::UnitY(), Vec3<double>(k, 0, 0))));
    parent = links.back();
    parent_centre = centre;
  }
  return links;
}

std::vector<MobilizedBody> Humanoid(SimTK::SimbodyMatterSubsystem& matter) {
  const std::vector<TreeBody> tree = HumanoidTree();
  std::vector<MobilizedBody> bodies;  // in the tree's order, the torso first
  for (const TreeBody& b : tree) {
    const SimTK::Body::Rigid body = RigidBody(b.mass, b.inertia.asDiagonal());
    MobilizedBody parent = b.parent < 0 ? matter.Ground() : bodies[b.parent];
    const Vec3<double> parent_centre = b.parent < 0 ? Vec3<double>::Zero() : tree[b.parent].centre;
    auto add = [&](auto mobilizer, const Transform& J) {
      bodies.push_back(Attach<decltype(mobilizer)>(parent, parent_centre, body, b.centre, J));
    };
    const Vec3<double> x = Vec3<double>::UnitX(), y = Vec3<double>::UnitY(), z = Vec3<double>::UnitZ();
    switch (b.joint) {
      case TreeJoint::kFixed:
        add(MobilizedBody::Weld(), Transform(ToSimTK(b.anchor)));
        break;
      case TreeJoint::kHingeX:
        add(MobilizedBody::Pin(), HingeFrame(x, b.anchor));
        break;
      case TreeJoint::kHingeY:
        add(MobilizedBody::Pin(), HingeFrame(y, b.anchor));
        break;
      case TreeJoint::kBall:
        add(MobilizedBody::Ball(), Transform(ToSimTK(b.anchor)));
        break;
      case TreeJoint::kUniversalZY:
        add(MobilizedBody::Universal(), UniversalFrame(z, y, b.anchor));
        break;
      case TreeJoint::kUniversalYX:
        add(MobilizedBody::Universal(), UniversalFrame(y, x, b.anchor));
        break;
      case TreeJoint::kUniversalXY:
        add(MobilizedBody::Universal(), UniversalFrame(x, y, b.anchor));
        break;
    }
  }
  bodies.erase(bodies.begin());  // tether's humanoid has no torso: its world is the torso
  return bodies;
}

std::vector<MobilizedBody> SpatialFourBar(SimTK::SimbodyMatterSubsystem& matter, SimTK::GeneralForceSubsystem& forces) {
  const Rssr r = RssrLinkage();
  const Vec3<double> crank_centre = 0.5 * (r.crank_pivot + r.crank_tip);
  const Vec3<double> coupler_centre = 0.5 * (r.crank_tip + r.rocker_tip);
  const Vec3<double> rocker_centre = 0.5 * (r.rocker_pivot + r.rocker_tip);
  MobilizedBody::Pin crank = Attach<MobilizedBody::Pin>(matter.Ground(), Vec3<double>::Zero(),
                                                        RigidBody(1.0, RodInertiaInWorld(r.crank_pivot, r.crank_tip)),
                                                        crank_centre, HingeFrame(r.crank_axis, r.crank_pivot));
  MobilizedBody::Ball coupler =
      Attach<MobilizedBody::Ball>(crank, crank_centre, RigidBody(1.0, RodInertiaInWorld(r.crank_tip, r.rocker_tip)),
                                  coupler_centre, Transform(ToSimTK(r.crank_tip)));
  MobilizedBody::Pin rocker = Attach<MobilizedBody::Pin>(
      matter.Ground(), Vec3<double>::Zero(), RigidBody(1.0, RodInertiaInWorld(r.rocker_pivot, r.rocker_tip)),
      rocker_centre, HingeFrame(r.rocker_axis, r.rocker_pivot));
  SimTK::Constraint::Ball(coupler, ToSimTK(r.rocker_tip - coupler_centre), rocker,
                          ToSimTK(r.rocker_tip - rocker_centre));
  SimTK::Force::MobilityConstantForce(forces, crank, 0, r.drive_torque);
  return {crank, coupler, rocker};
}

// the cranks, then the couplers
std::vector<MobilizedBody> FourBar(SimTK::SimbodyMatterSubsystem& matter, int n) {
  const double third = 1.0 / 12.0, thin = 1e-6;  // 1 m, 1 kg bars: only the moment about z acts in the plane
  const SimTK::Body::Rigid crank_body = RigidBody(1.0, Vec3<double>(third, thin, third).asDiagonal());
  const SimTK::Body::Rigid coupler_body = RigidBody(1.0, Vec3<double>(thin, third, third).asDiagonal());
  const Vec3<double> z = Vec3<double>::UnitZ();
  std::vector<MobilizedBody> cranks, couplers;
  for (int i = 0; i <= n; ++i) {
    cranks.push_back(Attach<MobilizedBody::Pin>(matter.Ground(), Vec3<double>::Zero(), crank_body,
                                                Vec3<double>(i, 0.5, 0), HingeFrame(z, Vec3<double>(i, 0, 0))));
  }
  for (int i = 0; i < n; ++i) {
    couplers.push_back(Attach<MobilizedBody::Pin>(cranks[i], Vec3<double>(i, 0.5, 0), coupler_body,
                                                  Vec3<double>(i + 0.5, 1, 0), HingeFrame(z, Vec3<double>(i, 1, 0))));
    SimTK::Constraint::PointOnLine(cranks[i + 1], SimTK::UnitVec3(0, 0, 1), SimTK::Vec3(0, 0.5, 0), couplers[i],
                                   SimTK::Vec3(0.5, 0, 0));
  }
  cranks.insert(cranks.end(), couplers.begin(), couplers.end());
  return cranks;
}

}  // namespace

SimbodyScene::SimbodyScene(Mechanism mechanism, int n) : matter_(system_), forces_(system_) {
  switch (mechanism) {
    case Mechanism::kHingeChain:
      bodies_ = HingeChain(matter_, n);
      break;
    case Mechanism::kHumanoid:
      bodies_ = Humanoid(matter_);
      break;
    case Mechanism::kRssr:
      bodies_ = SpatialFourBar(matter_, forces_);
      break;
    case Mechanism::kFourBar:
      bodies_ = FourBar(matter_, n);
      break;
    case Mechanism::kChain:
      throw std::logic_error("Simbody builds no chain of particles");
  }
  const bool planar = mechanism == Mechanism::kFourBar;
  SimTK::Force::Gravity(forces_, matter_, SimTK::UnitVec3(planar ? SimTK::Vec3(0, -1, 0) : SimTK::Vec3(0, 0, -1)),
                        9.81);
  system_.realizeTopology();
  initial_ = system_.getDefaultState();
  if (planar) {  // cranks at -1 rad/s; couplers (relative to their cranks) at +1: they translate
    for (size_t k = 0; k < bodies_.size(); ++k) bodies_[k].setOneU(initial_, 0, k <= bodies_.size() / 2 ? -1.0 : 1.0);
  }
  system_.realize(initial_, SimTK::Stage::Velocity);
}

std::vector<Vec3<double>> SimbodyScene::Run(const SimbodySettings& settings, double duration,
                                            const std::function<void(const SimTK::State&)>& observe, int* steps) const {
  std::unique_ptr<SimTK::Integrator> integrator;
  if (settings.integrator == SimbodyIntegrator::kCPodes) {
    integrator = std::make_unique<SimTK::CPodesIntegrator>(system_);
  } else {
    integrator = std::make_unique<SimTK::RungeKuttaMersonIntegrator>(system_);
  }
  integrator->setAccuracy(settings.accuracy);
  integrator->setFinalTime(duration);
  integrator->setReturnEveryInternalStep(observe != nullptr);
  integrator->initialize(initial_);
  while (integrator->getTime() < duration) {
    integrator->stepTo(duration);
    if (observe) observe(integrator->getState());
  }
  if (steps) *steps = integrator->getNumStepsTaken();
  std::vector<Vec3<double>> centres;
  for (const MobilizedBody& body : bodies_) {
    const SimTK::Vec3& p = body.getBodyOriginLocation(integrator->getState());
    centres.emplace_back(p[0], p[1], p[2]);
  }
  return centres;
}

double SimbodyScene::Violation(const SimTK::State& state) const {
  double worst = 0.0;
  for (SimTK::ConstraintIndex c(0); c < matter_.getNumConstraints(); ++c) {
    const SimTK::Vector errors = matter_.getConstraint(c).getPositionErrorsAsVector(state);
    for (int i = 0; i < errors.size(); ++i) worst = std::max(worst, std::abs(errors[i]));
  }
  return worst;
}

}  // namespace tether::bench
