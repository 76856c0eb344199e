// What one step of the shipped pendulum costs with each integrator (h = 1e-3).
#include <benchmark/benchmark.h>

#include "bench_models.h"

namespace tether::bench {
namespace {

void StepPendulum(benchmark::State& state, Integrator integrator) { StepModel(state, Pendulum(integrator, 1e-3)); }

BENCHMARK_CAPTURE(StepPendulum, euler, Integrator::kEuler)->Unit(benchmark::kNanosecond);
BENCHMARK_CAPTURE(StepPendulum, symplectic_euler, Integrator::kSymplecticEuler)->Unit(benchmark::kNanosecond);
BENCHMARK_CAPTURE(StepPendulum, rk4, Integrator::kRk4)->Unit(benchmark::kNanosecond);
BENCHMARK_CAPTURE(StepPendulum, rk45, Integrator::kRk45)->Unit(benchmark::kNanosecond);

}  // namespace
}  // namespace tether::bench
