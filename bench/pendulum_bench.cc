// What one step of the shipped pendulum costs with each integrator (h = 1e-3).
#include <benchmark/benchmark.h>

#include "bench_models.h"
#include "tether/dynamics/default_gains.h"
#include "tether/dynamics/integrators.h"

namespace tether::bench {
namespace {

void StepPendulum(benchmark::State& state, Integrator integrator) {
  const Model<double> model = Pendulum(integrator, 1e-3);
  Workspace<double> ws(model);
  GainsInUse(model, &ws.alpha, &ws.beta);
  VecX<double> q = model.q0, v = model.v0;
  double t = 0.0;
  for (auto _ : state) {
    Advance(model, t, 1e-3, &ws, &q, &v);
    t += 1e-3;
    benchmark::DoNotOptimize(q.data());
  }
}

BENCHMARK_CAPTURE(StepPendulum, euler, Integrator::kEuler)->Unit(benchmark::kNanosecond);
BENCHMARK_CAPTURE(StepPendulum, symplectic_euler, Integrator::kSymplecticEuler)->Unit(benchmark::kNanosecond);
BENCHMARK_CAPTURE(StepPendulum, rk4, Integrator::kRk4)->Unit(benchmark::kNanosecond);
BENCHMARK_CAPTURE(StepPendulum, rk45, Integrator::kRk45)->Unit(benchmark::kNanosecond);

}  // namespace
}  // namespace tether::bench
