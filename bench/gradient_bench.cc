// The cost of one loss gradient against the number of parameters P, for the three ways tether computes it:
//   implicit    Jets with the implicit-function KKT solve (JetLossGradient, the default): ceil(P / kJetStride)
//               Jet runs, each factoring the double Schur matrix once per solve;
//   jet_factor  the Jet-factorization oracle (JetLossGradient with factor_jet_matrices): the same Jet runs, but
//               every solve factors the matrix of Jets itself;
//   central     central differences (CentralDifferenceLossGradient): 1 + 2P plain double runs.
// Each is also reported as a multiple of one plain double simulation of the same model and observations
// (ObservationResiduals<double>), timed in the same loop, plain runs after every gradient (thread CPU time):
// counters `x_plain_simulation` (gradient / plain) and `plain_ms`.
//
// Model: HorizontalChainScene (unit masses on 1 m links, released horizontal, rk4, h = 1e-3 s, Baumgarte
// alpha = 20, beta = 100, solver auto, which is sparse for both sizes) of n = 20 and 200 particles, simulated
// for kDuration. Parameters: P = 1 ... 32 distinct quantities, alternately the mass of particle k and the length
// of link k (/bodies/0/mass, /constraints/0/length, /bodies/1/mass, ...), so the same pointers serve both
// chains. Observations: x and y of the middle and the last particle at 10 evenly spaced times (40 cells), the
// nominal simulation shifted by 1 cm so that the loss and the gradient are not zero.
// All three methods run in full for every P on both chains (the oracle costs about twice the implicit path,
// so it needs no shorter run).
// bench/gradient_cost.py runs this and prints the Markdown table quoted in the README.
#include <time.h>

#include <cmath>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "bench_models.h"
#include "tether/autodiff/adjoint.h"
#include "tether/autodiff/residuals.h"
#include "tether/dynamics/scene_reader.h"

namespace tether::bench {
namespace {

constexpr double kDuration = 0.2;  // s: 200 steps of 1e-3 s
constexpr int kObservationTimes = 10;

enum class Method { kImplicit, kJetFactor, kCentral, kAdjoint };

struct Problem {
  Scene scene;
  ParameterSet parameters;
  Observations observations;
};

std::vector<std::string> Pointers(int count) {
  std::vector<std::string> pointers;
  for (int i = 0; i < count; ++i) {
    pointers.push_back(i % 2 == 0 ? "/bodies/" + std::to_string(i / 2) + "/mass"
                                  : "/constraints/" + std::to_string(i / 2) + "/length");
  }
  return pointers;
}

Problem MakeProblem(int n, int count, double duration) {
  Problem problem;
  problem.scene = ParseScene(HorizontalChainScene(n, duration), "chain" + std::to_string(n) + ".json");
  problem.parameters = ParameterSet(problem.scene, Pointers(count));
  Observations& obs = problem.observations;
  obs.path = "in memory";
  for (int body : {n / 2 - 1, n - 1}) {
    const std::string name = "p" + std::to_string(body);
    obs.columns.push_back({name + ".x", TrajectoryColumn::Kind::kConfiguration, 2 * body});
    obs.columns.push_back({name + ".y", TrajectoryColumn::Kind::kConfiguration, 2 * body + 1});
  }
  for (int k = 1; k <= kObservationTimes; ++k) {
    obs.times.push_back(duration * k / kObservationTimes);
    obs.values.push_back(std::vector<double>(obs.columns.size(), 0.0));
    obs.lines.push_back(k + 1);
  }
  // observed against zero, the residuals are the simulated values
  const VecX<double> simulated = ObservationResiduals(problem.scene.model, obs);
  int cell = 0;
  for (std::vector<double>& row : obs.values) {
    for (double& value : row) value = simulated[cell++] + 0.01;
  }
  return problem;
}

double ThreadSeconds() {
  timespec now;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &now);
  return now.tv_sec + 1e-9 * now.tv_nsec;
}

// One plain double simulation; returns its thread CPU seconds.
double TimePlainSimulation(const Problem& problem) {
  const double start = ThreadSeconds();
  benchmark::DoNotOptimize(ObservationResiduals(problem.scene.model, problem.observations).data());
  return ThreadSeconds() - start;
}

void SetCounters(benchmark::State& state, const Problem& problem, double plain) {
  state.counters["n"] = static_cast<double>(state.range(0));
  state.counters["P"] = static_cast<double>(problem.parameters.size());
  state.counters["duration_s"] = problem.scene.model.simulation.duration;
  state.counters["plain_ms"] = 1e3 * plain;
}

LossGradient Compute(const Problem& problem, Method method) {
  switch (method) {
    case Method::kCentral:
      return CentralDifferenceLossGradient(problem.scene.model, problem.parameters, problem.observations);
    case Method::kAdjoint:
      return AdjointLossGradient(problem.scene.model, problem.parameters, problem.observations);
    default:
      return JetLossGradient(problem.scene.model, problem.parameters, problem.observations,
                             method == Method::kJetFactor);
  }
}

// Every iteration times one gradient and then, with the benchmark clock paused, plain simulations (at least one,
// and until they add up to a quarter of the gradient's time), so that both see the same load, clock speed and
// heap: the ratio is the mean gradient time over the mean plain time.
void Gradient(benchmark::State& state, Method method) {
  const Problem problem =
      MakeProblem(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)), kDuration);
  double gradient_seconds = 0.0, plain_seconds = 0.0;
  int plain_runs = 0;
  for (auto _ : state) {
    const double start = ThreadSeconds();
    const LossGradient g = Compute(problem, method);
    benchmark::DoNotOptimize(g.gradient.data());
    const double seconds = ThreadSeconds() - start;
    gradient_seconds += seconds;
    state.PauseTiming();
    double plain = 0.0;
    do {
      plain += TimePlainSimulation(problem);
      ++plain_runs;
    } while (plain < 0.25 * seconds);
    plain_seconds += plain;
    state.ResumeTiming();
  }
  const double plain = plain_seconds / plain_runs;
  SetCounters(state, problem, plain);
  state.counters["x_plain_simulation"] = gradient_seconds / static_cast<double>(state.iterations()) / plain;
  const int count = problem.parameters.size();
  state.counters["runs"] = method == Method::kCentral ? 1 + 2 * count : (count + kJetStride - 1) / kJetStride;
}

// One plain double simulation (what the ratios divide by), timed by the benchmark loop for reference.
void PlainSimulation(benchmark::State& state) {
  const Problem problem = MakeProblem(static_cast<int>(state.range(0)), 1, kDuration);
  double seconds = 0.0;
  for (auto _ : state) seconds += TimePlainSimulation(problem);
  SetCounters(state, problem, seconds / static_cast<double>(state.iterations()));
}

void Sizes(benchmark::internal::Benchmark* b) {
  b->ArgNames({"n", "P"});
  for (int n : {20, 200}) {
    for (int p : {1, 2, 4, 8, 16, 32}) b->Args({n, p});
  }
  b->Unit(benchmark::kMillisecond);
}

BENCHMARK(PlainSimulation)->ArgNames({"n", "P"})->Args({20, 1})->Args({200, 1})->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(Gradient, implicit, Method::kImplicit)->Apply(Sizes);
BENCHMARK_CAPTURE(Gradient, jet_factor, Method::kJetFactor)->Apply(Sizes);
BENCHMARK_CAPTURE(Gradient, central, Method::kCentral)->Apply(Sizes);
BENCHMARK_CAPTURE(Gradient, adjoint, Method::kAdjoint)->Apply(Sizes);

}  // namespace
}  // namespace tether::bench
