// Time per step against system size for each KKT solver path: chains of particles (two integrators), binary
// trees of particles, N-four-bars of rigid bars (closed loops), and 3D chains and binary trees of rigid rods on
// hinges (5 rows a joint). The systems move during the benchmark, so
// every step works on a changing configuration. Linear growth on the sparse path is the goal (a chain's Schur
// complement is tridiagonal, a tree's factors without fill); the four-bars show where the dense path pays.
#include <benchmark/benchmark.h>

#include "bench_models.h"

namespace tether::bench {
namespace {

void StepChain(benchmark::State& state, Integrator integrator, KktSolver solver) {
  StepModel(state, HorizontalChain(static_cast<int>(state.range(0)), integrator, solver));
}

void StepTree(benchmark::State& state, KktSolver solver) {
  StepModel(state, BinaryTree(static_cast<int>(state.range(0)), solver));
}

void StepFourBar(benchmark::State& state, KktSolver solver) {
  StepModel(state, FourBar(static_cast<int>(state.range(0)), solver));
}

void StepHingeChain(benchmark::State& state, Integrator integrator, KktSolver solver) {
  StepModel(state, HingeChain(static_cast<int>(state.range(0)), integrator, solver));
}

void StepHingeTree(benchmark::State& state, KktSolver solver) {
  StepModel(state, HingeTree(static_cast<int>(state.range(0)), solver));
}

// 1-2-5 steps, evenly spaced on the log axes of studies/scaling.
void Sizes(benchmark::internal::Benchmark* b, int largest) {
  for (int n : {1, 2, 5, 10, 20, 50, 100, 200, 500, 1000, 2000, 5000}) {
    if (n <= largest) b->Arg(n);
  }
  b->Unit(benchmark::kMicrosecond);
}

BENCHMARK_CAPTURE(StepChain, rk4_sparse, Integrator::kRk4, KktSolver::kSparse)->Apply([](auto* b) { Sizes(b, 5000); });
BENCHMARK_CAPTURE(StepChain, rk4_dense, Integrator::kRk4, KktSolver::kDense)->Apply([](auto* b) { Sizes(b, 1000); });
BENCHMARK_CAPTURE(StepChain, symplectic_euler_sparse, Integrator::kSymplecticEuler, KktSolver::kSparse)
    ->Apply([](auto* b) { Sizes(b, 5000); });
BENCHMARK_CAPTURE(StepChain, symplectic_euler_dense, Integrator::kSymplecticEuler, KktSolver::kDense)
    ->Apply([](auto* b) { Sizes(b, 1000); });

BENCHMARK_CAPTURE(StepTree, rk4_sparse, KktSolver::kSparse)->Apply([](auto* b) { Sizes(b, 5000); });
BENCHMARK_CAPTURE(StepTree, rk4_dense, KktSolver::kDense)->Apply([](auto* b) { Sizes(b, 500); });

BENCHMARK_CAPTURE(StepFourBar, rk4_sparse, KktSolver::kSparse)->Apply([](auto* b) { Sizes(b, 500); });
BENCHMARK_CAPTURE(StepFourBar, rk4_dense, KktSolver::kDense)->Apply([](auto* b) { Sizes(b, 100); });

BENCHMARK_CAPTURE(StepHingeChain, rk4_sparse, Integrator::kRk4, KktSolver::kSparse)
    ->Apply([](auto* b) { Sizes(b, 1000); });
BENCHMARK_CAPTURE(StepHingeChain, rk4_dense, Integrator::kRk4, KktSolver::kDense)->Apply([](auto* b) { Sizes(b, 200); });
BENCHMARK_CAPTURE(StepHingeChain, symplectic_euler_sparse, Integrator::kSymplecticEuler, KktSolver::kSparse)
    ->Apply([](auto* b) { Sizes(b, 1000); });
// auto: the tree elimination (tree_elimination.h), which the 3D hinge chains and trees take
BENCHMARK_CAPTURE(StepHingeChain, rk4_tree, Integrator::kRk4, KktSolver::kAuto)->Apply([](auto* b) { Sizes(b, 1000); });
BENCHMARK_CAPTURE(StepHingeTree, rk4_sparse, KktSolver::kSparse)->Apply([](auto* b) { Sizes(b, 1000); });
BENCHMARK_CAPTURE(StepHingeTree, rk4_dense, KktSolver::kDense)->Apply([](auto* b) { Sizes(b, 200); });
BENCHMARK_CAPTURE(StepHingeTree, rk4_tree, KktSolver::kAuto)->Apply([](auto* b) { Sizes(b, 1000); });

}  // namespace
}  // namespace tether::bench
