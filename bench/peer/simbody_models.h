// The peer benchmark's accuracy scenes in Simbody (3.7, Debian's libsimbody-dev), each in Simbody's own terms: a
// tree of mobilizers in reduced coordinates, and constraints only where a loop must be closed.
//
// Every body's frame sits at its centre of mass with the world's axes at the start, its inertia written in them;
// a joint's mobilizer frames are the joint's frame J in the world seen from the parent and from the body,
// F = X_GP^-1 J and M = X_GB^-1 J, so that the scene starts at q = 0 (X_FM = identity). A Pin turns about J's z,
// a Universal about J's x and then the new y, a Ball (quaternion) about J's origin.
//   hinge chain   bench_models.h's HingeChain: n rods (1 kg, 1 m, radius 2 cm) on Pins about y, released
//                 horizontal along +x, gravity -9.81 z.
//   humanoid      humanoid_tree.h's tree: the torso on a Weld; hips Ball, knees and elbows Pin, abdomen,
//                 ankles and shoulders Universal with the tree's axis pairs, the pelvis a Pin about x.
//   RSSR          rssr_linkage.h: the crank and the rocker on Pins, the coupler on a Ball at the crank's tip, a
//                 Constraint::Ball closing the loop at the rocker's tip; the motor a MobilityConstantForce.
//   four-bar      bench_models.h's FourBar(n) in the x-y plane, gravity -9.81 y: cranks on Pins about z at
//                 (i, 0, 0), coupler i on a Pin at crank i's tip, each loop closed at crank i + 1's tip by a
//                 Constraint::PointOnLine (the coupler's end on the line along z through the tip: the two equations
//                 of a planar pin; a Ball would add a third, redundant one); cranks turning at -1 rad/s about z.
// Gravity is Force::Gravity. Integration: Simbody's error-controlled integrators at a set accuracy (its relative
// error per step), with its default constraint tolerance (accuracy / 10) and its projection of positions and
// velocities onto the constraints whenever they exceed it.
#pragma once

#include <Simbody.h>

#include <functional>
#include <vector>

#include "tether/dynamics/scalars/scalar.h"
#include "tether_models.h"

namespace tether::bench {

enum class SimbodyIntegrator { kRungeKuttaMerson, kCPodes };

struct SimbodySettings {
  SimbodyIntegrator integrator = SimbodyIntegrator::kRungeKuttaMerson;
  double accuracy = 1e-6;
};

class SimbodyScene {
 public:
  // kHingeChain (n rods), kHumanoid, kRssr or kFourBar (n parallelograms); throws std::logic_error otherwise.
  SimbodyScene(Mechanism mechanism, int n);
  SimbodyScene(const SimbodyScene&) = delete;
  SimbodyScene& operator=(const SimbodyScene&) = delete;

  // Runs the scene from its initial state to `duration`; returns the bodies' centres of mass at the end, in tether's
  // order (tether_models.h; the humanoid without its torso). `observe` sees the state after every internal step
  // when given; `steps` receives the number of steps taken. Throws SimTK::Exception when the integrator fails.
  std::vector<Vec3<double>> Run(const SimbodySettings& settings, double duration,
                                const std::function<void(const SimTK::State&)>& observe = nullptr,
                                int* steps = nullptr) const;

  // The largest position error of the scene's constraints, m (0 for the trees; the Ball mobilizers' quaternion
  // norms are not constraints). Needs a state realized to positions.
  double Violation(const SimTK::State& state) const;

 private:
  SimTK::MultibodySystem system_;
  SimTK::SimbodyMatterSubsystem matter_;
  SimTK::GeneralForceSubsystem forces_;
  std::vector<SimTK::MobilizedBody> bodies_;  // in tether's order
  SimTK::State initial_;
};

}  // namespace tether::bench
