// What joint limits cost while they are not reached: whole steps of the run (Stepper::Step, which looks for
// events after each step) of a 3D hinge chain and of the humanoid of bench/peer (every joint named, so that both
// track their coordinates), with and without a range on every hinge wide enough never to be reached. A scene
// pays only for what it declares: the limited run should cost at most 10% more per step (issue 33).
#include <benchmark/benchmark.h>

#include <memory>

#include "bench_models.h"
#include "peer/tether_models.h"
#include "tether/dynamics/integration/stepper.h"

namespace tether::bench {
namespace {

constexpr int kStepsPerRun = 250;

// Every joint named; with `limited`, each hinge's angle held within +-10 rad (never reached in a run).
Model<double> Named(Model<double> model, bool limited) {
  for (size_t k = 0; k < model.joints.size(); ++k) {
    Joint<double>& joint = model.joints[k];
    if (joint.name.empty()) joint.name = "j" + std::to_string(k);
    if (limited && joint.type == JointType::kHinge) joint.range = {true, true, -10.0, 10.0, 0.5};
  }
  return model;
}

// Steps of a run, one item a step; a fresh run (its set-up untimed) every kStepsPerRun steps.
void StepRun(benchmark::State& state, const Model<double>& model) {
  RunOptions options;
  options.every = kStepsPerRun;
  std::unique_ptr<Stepper<double>> stepper;
  int step = kStepsPerRun;
  for (auto _ : state) {
    if (step == kStepsPerRun) {
      state.PauseTiming();
      stepper = std::make_unique<Stepper<double>>(model, options, [](const Sample<double>&) {});
      stepper->Start();
      step = 0;
      state.ResumeTiming();
    }
    stepper->Step();
    ++step;
    benchmark::DoNotOptimize(stepper->state().q.data());
  }
  state.SetItemsProcessed(state.iterations());
}

void HingeChainRun(benchmark::State& state, bool limited) {
  Model<double> model =
      Named(HingeChain(static_cast<int>(state.range(0)), Integrator::kRk4, KktSolver::kAuto), limited);
  model.simulation.duration = 10.0;
  StepRun(state, model);
}

void HumanoidRun(benchmark::State& state, bool limited) {
  StepRun(state, Named(TetherPeerScene(Mechanism::kHumanoid, 0, true, 10.0), limited));
}

BENCHMARK_CAPTURE(HingeChainRun, free, false)->Arg(10)->Arg(100)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(HingeChainRun, limited, true)->Arg(10)->Arg(100)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(HumanoidRun, free, false)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(HumanoidRun, limited, true)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace tether::bench
