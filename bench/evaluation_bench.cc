// Where one evaluation of the dynamics (ComputeAcceleration: v' at (q, v)) spends its time on the 3D scenes of the
// peer benchmark, part by part (docs/performance.md): the humanoid-sized tree (12 moving bodies, 51 rows), MuJoCo's
// humanoid.xml imported hanging by its torso (14 bodies, 63 rows; it needs MuJoCo's importer and sample models) and
// the 10- and 200-rod hinge chains (50 and 1000 rows), each at the state reached after 0.5 s of its rk4 run from rest,
// so that every velocity term is non-zero. EvaluationPart/PART/SCENE, PART one of
//   frames     UpdateFrames: every body's rotation and world angular velocity
//   forces     AccumulateForces: gravity and the gyroscopic torques
//   rows       EvaluateConstraintRows: values, Jacobian blocks and velocity products
//   assembly   AssembleSchur: S = J M^-1 J^T
//   factor     the sparse LDL^T's numeric factorization
//   solve      its pair of triangular solves
//   evaluation the whole of ComputeAcceleration (the parts above, the right-hand side and J^T lambda)
//   rk4_step   one rk4 step (four evaluations and the moves on SO(3) between them)
#include <benchmark/benchmark.h>

#include <functional>
#include <memory>
#include <string>

#include "peer/tether_models.h"
#include "tether/dynamics/effects/effects.h"
#include "tether/dynamics/integration/default_gains.h"
#include "tether/dynamics/integration/integrators.h"
#include "tether/dynamics/integration/simulator.h"
#include "tether/dynamics/model/configuration_space.h"
#include "tether/dynamics/solvers/constrained_dynamics.h"
#include "tether/dynamics/solvers/sparse_ldlt.h"
#include "tether/dynamics/solvers/workspace.h"

namespace tether::bench {
namespace {

constexpr double kSettleTime = 0.5;  // s of rk4 from rest before the state is timed

// A scene's model, its workspace at the settled state, and that state.
struct Evaluated {
  Evaluated(Mechanism mechanism, int size) : model(TetherPeerScene(mechanism, size, true, kSettleTime)) {
    RunReport report;
    const State<double> start = AssembledInitialState(model, &report);
    q = start.q;
    v = start.v;
    workspace = std::make_unique<Workspace<double>>(model, q);
    GainsInUse(model, &workspace->alpha, &workspace->beta);
    TimeIntegrator<double> integrator(model);
    for (double t = 0.0; t < kSettleTime; t += kPeerStep) integrator.Advance(t, kPeerStep, workspace.get(), &q, &v);
    acceleration.setZero(v.size());
    ComputeAcceleration(model, 0.0, q, v, workspace.get(), &acceleration);
  }
  Model<double> model;
  VecX<double> q, v, acceleration;
  std::unique_ptr<Workspace<double>> workspace;
};

void Part(benchmark::State& state, Mechanism mechanism, int size, const std::string& part) {
  Evaluated e(mechanism, size);
  Workspace<double>& ws = *e.workspace;
  SparseLdlt factor(*ws.pattern);
  factor.Factor(ws.kkt.schur);
  VecX<double> x = ws.kkt.rhs, q = e.q, v = e.v;
  TimeIntegrator<double> integrator(e.model);
  const std::function<void()> run = [&]() -> std::function<void()> {
    if (part == "frames") return [&] { UpdateFrames(e.model, e.q, e.v, true, &ws.frames); };
    if (part == "forces") {
      return [&] {
        ws.force.setZero();
        AccumulateForces(e.model, ws.coordinates, ws.principal_inertia, ws.frames, 0.0, e.q, e.v, &ws.force);
      };
    }
    if (part == "rows") {
      return [&] { EvaluateConstraintRows(e.model, ws.constraints, ws.frames, e.q, e.v, true, &ws.rows); };
    }
    if (part == "assembly") return [&] { AssembleSchur(&ws); };
    if (part == "factor") return [&] { benchmark::DoNotOptimize(factor.Factor(ws.kkt.schur)); };
    if (part == "solve") return [&] { factor.SolveInPlace(&x); };
    if (part == "evaluation") return [&] { ComputeAcceleration(e.model, 0.0, e.q, e.v, &ws, &e.acceleration); };
    return [&] {  // rk4_step, always from the settled state
      q = e.q;
      v = e.v;
      integrator.Advance(0.0, kPeerStep, &ws, &q, &v);
    };
  }();
  for (auto _ : state) {
    run();
    benchmark::ClobberMemory();
  }
}

void Register() {
  struct Scene {
    const char* name;
    Mechanism mechanism;
    int size;  // of a chain
  };
  for (const auto& [scene, mechanism, size] :
       {Scene{"humanoid", Mechanism::kHumanoid, 0}, Scene{"humanoid_file", Mechanism::kHumanoidFile, 0},
        Scene{"hinge_chain10", Mechanism::kHingeChain, 10}, Scene{"hinge_chain200", Mechanism::kHingeChain, 200}}) {
    for (const char* part : {"frames", "forces", "rows", "assembly", "factor", "solve", "evaluation", "rk4_step"}) {
      benchmark::RegisterBenchmark((std::string("EvaluationPart/") + part + "/" + scene).c_str(), Part, mechanism, size,
                                   std::string(part))
          ->Unit(benchmark::kMicrosecond);
    }
  }
}

[[maybe_unused]] const bool registered = (Register(), true);

}  // namespace
}  // namespace tether::bench
