// A step allocates nothing (docs/architecture.md, principle 2): a run of 2K steps makes exactly as many heap
// allocations as a run of K steps of the same model (the difference being the steps), for every integrator, both KKT
// paths, every stabilization (the singular-configuration guard's projections included, on a four-bar near its collinear
// configurations) and for Jets.
//
// The count comes from this program's own malloc, calloc and realloc, which count and forward to glibc's
// (__libc_malloc ...). They replace the C library's for the whole process, Eigen's and operator new's
// allocations included, which is why this is a program of its own, and why it is not built with the sanitizers
// (they replace malloc themselves).
#include <gtest/gtest.h>

#include <atomic>
#include <cstddef>
#include <iterator>
#include <string>
#include <vector>

#include "test_scenes.h"
#include "tether/dynamics/integration/simulator.h"
#include "tether/dynamics/io/scene_reader.h"

extern "C" {
void* __libc_malloc(size_t size);
void* __libc_calloc(size_t count, size_t size);
void* __libc_realloc(void* pointer, size_t size);

static std::atomic<long> allocations{0};

void* malloc(size_t size) {
  allocations.fetch_add(1, std::memory_order_relaxed);
  return __libc_malloc(size);
}
void* calloc(size_t count, size_t size) {
  allocations.fetch_add(1, std::memory_order_relaxed);
  return __libc_calloc(count, size);
}
void* realloc(void* pointer, size_t size) {
  allocations.fetch_add(1, std::memory_order_relaxed);
  return __libc_realloc(pointer, size);
}
}

namespace tether {
namespace {

constexpr Integrator kIntegrators[] = {Integrator::kEuler, Integrator::kSymplecticEuler, Integrator::kRk4,
                                       Integrator::kRk45};
constexpr const char* kIntegratorNames[] = {"euler", "symplectic_euler", "rk4", "rk45"};

// Heap allocations of one whole run of `steps` steps, output at the start and the end only.
template <typename T>
long AllocationsOfARun(const Model<T>& model, int steps) {
  Model<T> run = model;
  run.simulation.duration = steps * run.simulation.step;
  RunOptions options;
  options.every = steps;
  const long before = allocations.load();
  Simulate<T>(run, options, [](const Sample<T>&) {});
  return allocations.load() - before;
}

constexpr Stabilization kEveryStabilization[] = {Stabilization::kNone, Stabilization::kBaumgarte,
                                                 Stabilization::kProjection};

// For the integrators from `first_integrator` on, both KKT paths and the given stabilizations.
template <typename T>
void ExpectStepsAllocateNothing(const Model<T>& model, int steps, int first_integrator = 0,
                                const std::vector<Stabilization>& stabilizations = {std::begin(kEveryStabilization),
                                                                                    std::end(kEveryStabilization)}) {
  for (int i = first_integrator; i < 4; ++i) {
    for (KktSolver solver : {KktSolver::kSparse, KktSolver::kDense}) {
      for (Stabilization stabilization : stabilizations) {
        Model<T> m = model;
        m.simulation.integrator = kIntegrators[i];
        m.simulation.solver = solver;
        m.stabilization.method = stabilization;
        SCOPED_TRACE(std::string(kIntegratorNames[i]) + (solver == KktSolver::kDense ? ", dense, " : ", sparse, ") +
                     std::to_string(static_cast<int>(stabilization)));
        const long short_run = AllocationsOfARun(m, steps);
        EXPECT_EQ(AllocationsOfARun(m, 2 * steps), short_run);
      }
    }
  }
}

// n particles on 0.5 m links, hanging from the origin, released horizontal
Model<double> Chain(int n) {
  std::string bodies, constraints;
  for (int k = 0; k < n; ++k) {
    const std::string name = "\"p" + std::to_string(k) + "\"";
    bodies += std::string(k ? "," : "") + "{\"name\": " + name + ", \"type\": \"particle\", \"mass\": 1, " +
              "\"position\": [" + std::to_string(0.5 * (k + 1)) + ", 0]}";
    constraints += std::string(k ? "," : "") + "{\"type\": \"distance\", \"bodies\": [" +
                   (k ? "\"p" + std::to_string(k - 1) + "\"" : std::string("\"world\"")) + ", " + name + "]}";
  }
  return testing::SceneFromJson("{\"bodies\": [" + bodies + "], \"constraints\": [" + constraints +
                                "], \"effects\": [{\"type\": \"gravity\", \"acceleration\": [0, -9.81]}]}");
}

TEST(StepAllocation, NoneOnAChain) { ExpectStepsAllocateNothing(Chain(20), 200); }

// scenes/four_bar.json for 1.6 and 3.2 s, rk4 and rk45: near the parallelogram's collinear configurations a
// Baumgarte run projects onto the constraints (schur_solver.h's conditioning flag), 7 and 15 times. Without
// stabilization the pass is a matter of luck (rk4 at steps within 0.3% of 1e-3 ends 0.005 to 18 J off its energy,
// or runs away), so that run is left to the chains.
TEST(StepAllocation, NoneOnAFourBarThroughASingularPass) {
  const Model<double> four_bar = ReadSceneFile(TETHER_SOURCE_DIR "/scenes/four_bar.json").model;
  ExpectStepsAllocateNothing(four_bar, 1600, 2, {Stabilization::kBaumgarte, Stabilization::kProjection});
}

TEST(StepAllocation, NoneWithJets) { ExpectStepsAllocateNothing(CastModel<Jet>(Chain(10)), 100); }

}  // namespace
}  // namespace tether
