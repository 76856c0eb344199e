// Time per step against the number of particles in a chain, for each KKT solver path and two integrators.
// The chain falls from horizontal, so every step works on a changing configuration. Linear growth on the
// sparse path is the goal (the Schur complement of a chain is tridiagonal).
#include <benchmark/benchmark.h>

#include "bench_models.h"
#include "tether/dynamics/default_gains.h"
#include "tether/dynamics/integrators.h"

namespace tether::bench {
namespace {

void StepChain(benchmark::State& state, Integrator integrator, KktSolver solver) {
  const int n = static_cast<int>(state.range(0));
  const Model<double> model = HorizontalChain(n, integrator, solver);
  Workspace<double> ws(model);
  GainsInUse(model, &ws.alpha, &ws.beta);
  VecX<double> q = model.q0, v = model.v0;
  double t = 0.0;
  const double h = model.simulation.step;
  for (auto _ : state) {
    Advance(model, t, h, &ws, &q, &v);
    t += h;
    benchmark::DoNotOptimize(q.data());
  }
  state.counters["particles"] = n;
  state.SetItemsProcessed(state.iterations());  // items = steps
}

void Sizes(benchmark::internal::Benchmark* b, int largest) {
  for (int n : {10, 20, 50, 100, 200, 500, 1000}) {
    if (n <= largest) b->Arg(n);
  }
  b->Unit(benchmark::kMicrosecond);
}

BENCHMARK_CAPTURE(StepChain, rk4_sparse, Integrator::kRk4, KktSolver::kSparse)->Apply([](auto* b) { Sizes(b, 1000); });
BENCHMARK_CAPTURE(StepChain, rk4_dense, Integrator::kRk4, KktSolver::kDense)->Apply([](auto* b) { Sizes(b, 500); });
BENCHMARK_CAPTURE(StepChain, symplectic_euler_sparse, Integrator::kSymplecticEuler, KktSolver::kSparse)
    ->Apply([](auto* b) { Sizes(b, 1000); });
BENCHMARK_CAPTURE(StepChain, symplectic_euler_dense, Integrator::kSymplecticEuler, KktSolver::kDense)
    ->Apply([](auto* b) { Sizes(b, 500); });

}  // namespace
}  // namespace tether::bench
