// The cost of one loss gradient against the number of parameters P, for the four ways tether computes it:
//   implicit    Jets with the implicit-function KKT solve (JetLossGradient): ceil(P / kJetStride) Jet runs,
//               each factoring the double Schur matrix once per solve;
//   jet_factor  the Jet-factorization oracle (JetLossGradient with factor_jet_matrices): the same Jet runs, but
//               every solve factors the matrix of Jets itself (run up to P = 32 only: a test oracle);
//   central     central differences (CentralDifferenceLossGradient): 1 + 2P plain double runs;
//   adjoint     the discrete adjoint (AdjointLossGradient): one double run and one recorded replay, whatever P.
// Each is also reported as a multiple of one plain double simulation of the same model and observations
// (ObservationResiduals<double>), timed in the same loop, plain runs after every gradient (thread CPU time):
// counters `x_plain_simulation` (gradient / plain), `plain_ms`, and for the adjoint `memory_mb` (the states and
// the largest record it kept, AdjointReport).
//
// Models (argument n), all simulated for kDuration with rk4, h = 1e-3 s:
//   n = 20, 200  HorizontalChainScene (unit masses on 1 m links, released horizontal, Baumgarte alpha = 20,
//                beta = 100, solver auto, which is sparse for both sizes). Parameters: alternately the mass of
//                particle k and the length of link k (/bodies/0/mass, /constraints/0/length, /bodies/1/mass,
//                ...), then, past the 2n of those, the values of a force schedule on the last particle (a knot
//                every kDuration / knots, both components). Observations: x and y of the middle and the last
//                particle at 10 evenly spaced times (40 cells).
//   n = 7        scenes/robot_arm.json, the 7-link 3D arm on hinges driven by joint-torque schedules. Parameters:
//                the links' masses, then their principal moments (21), then the values of the seven torque
//                schedules, re-made with as many knots as P needs. Observations: x, y and z of links 4 and 7
//                at 10 times (60 cells).
// The observations are the nominal simulation shifted by 1 cm, so that the loss and the gradient are not zero.
// bench/gradient_cost.py runs this and prints the Markdown table quoted in the README.
#include <benchmark/benchmark.h>
#include <time.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <string>
#include <vector>

#include "bench_models.h"
#include "tether/autodiff/adjoint.h"
#include "tether/autodiff/residuals.h"
#include "tether/dynamics/io/scene_reader.h"

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

constexpr int kArm = 7;  // the argument n that stands for the 3D arm

// A schedule of `knots` zero values of `components` components, knots evenly spaced over [0, kDuration].
nlohmann::json ZeroSchedule(int knots, int components) {
  nlohmann::json times = nlohmann::json::array(), values = nlohmann::json::array();
  for (int j = 0; j < knots; ++j) {
    times.push_back(knots == 1 ? 0.0 : kDuration * j / (knots - 1));
    values.push_back(components == 1 ? nlohmann::json(0.0) : nlohmann::json(std::vector<double>(components, 0.0)));
  }
  return {{"times", times}, {"values", values}};
}

// The chain's document and P pointers: masses and lengths alternately, then force-schedule values.
nlohmann::json ChainProblem(int n, int count, std::vector<std::string>* pointers) {
  nlohmann::json scene = HorizontalChainScene(n, kDuration);
  for (int i = 0; i < std::min(count, 2 * n); ++i) {
    pointers->push_back(i % 2 == 0 ? "/bodies/" + std::to_string(i / 2) + "/mass"
                                   : "/constraints/" + std::to_string(i / 2) + "/length");
  }
  const int values = count - 2 * n;
  if (values <= 0) return scene;
  const int knots = std::max(2, (values + 1) / 2);
  scene["effects"].push_back({{"type", "force"}, {"body", "p" + std::to_string(n - 1)}, {"schedule", ZeroSchedule(knots, 2)}});
  const std::string effect = "/effects/" + std::to_string(scene["effects"].size() - 1) + "/schedule/values/";
  for (int i = 0; i < values; ++i) pointers->push_back(effect + std::to_string(i / 2) + "/" + std::to_string(i % 2));
  return scene;
}

// The arm's document and P pointers: masses, principal moments, then joint-torque schedule values.
nlohmann::json ArmProblem(int count, std::vector<std::string>* pointers) {
  std::ifstream file(TETHER_SOURCE_DIR "/scenes/robot_arm.json");
  nlohmann::json scene = nlohmann::json::parse(file);
  scene["simulation"]["duration"] = kDuration;
  for (int i = 0; i < std::min(count, 4 * kArm); ++i) {
    pointers->push_back(i < kArm ? "/bodies/" + std::to_string(i) + "/mass"
                                 : "/bodies/" + std::to_string((i - kArm) / 3) + "/inertia/" + std::to_string((i - kArm) % 3));
  }
  const int values = count - 4 * kArm;
  if (values <= 0) return scene;
  const int knots = std::max(2, (values + kArm - 1) / kArm);
  std::vector<std::string> schedules;
  for (size_t e = 0; e < scene["effects"].size(); ++e) {
    if (scene["effects"][e]["type"] != "joint_torque") continue;
    scene["effects"][e]["schedule"] = ZeroSchedule(knots, 1);
    schedules.push_back("/effects/" + std::to_string(e) + "/schedule/values/");
  }
  for (int i = 0; i < values; ++i) pointers->push_back(schedules[i % kArm] + std::to_string(i / kArm));
  return scene;
}

Problem MakeProblem(int n, int count) {
  Problem problem;
  std::vector<std::string> pointers;
  const nlohmann::json document = n == kArm ? ArmProblem(count, &pointers) : ChainProblem(n, count, &pointers);
  problem.scene = ParseScene(document, n == kArm ? "robot_arm.json" : "chain" + std::to_string(n) + ".json");
  problem.parameters = ParameterSet(problem.scene, pointers);
  Observations& obs = problem.observations;
  obs.path = "in memory";
  const Model<double>& model = problem.scene.model;
  const std::vector<int> observed = n == kArm ? std::vector<int>{3, 6} : std::vector<int>{n / 2 - 1, n - 1};
  for (int body : observed) {
    const std::string& name = model.bodies[body].name;
    for (int k = 0; k < model.dimension; ++k) {
      obs.columns.push_back({name + "." + "xyz"[k], TrajectoryColumn::Kind::kConfiguration,
                             model.bodies[body].q_offset + k});
    }
  }
  for (int k = 1; k <= kObservationTimes; ++k) {
    obs.times.push_back(kDuration * k / kObservationTimes);
    obs.values.push_back(std::vector<double>(obs.columns.size(), 0.0));
    obs.lines.push_back(k + 1);
  }
  // observed against zero, the residuals are the simulated values
  const VecX<double> simulated = ObservationResiduals(model, obs);
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

LossGradient Compute(const Problem& problem, Method method, AdjointReport* report) {
  switch (method) {
    case Method::kCentral:
      return CentralDifferenceLossGradient(problem.scene.model, problem.parameters, problem.observations);
    case Method::kAdjoint:
      return AdjointLossGradient(problem.scene.model, problem.parameters, problem.observations, 0, report);
    default:
      return JetLossGradient(problem.scene.model, problem.parameters, problem.observations,
                             method == Method::kJetFactor);
  }
}

// Every iteration times one gradient and then, with the benchmark clock paused, plain simulations (at least one,
// and until they add up to a quarter of the gradient's time), so that both see the same load, clock speed and
// heap: the ratio is the mean gradient time over the mean plain time.
void Gradient(benchmark::State& state, Method method) {
  const Problem problem = MakeProblem(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)));
  AdjointReport report;
  double gradient_seconds = 0.0, plain_seconds = 0.0;
  int plain_runs = 0;
  for (auto _ : state) {
    const double start = ThreadSeconds();
    const LossGradient g = Compute(problem, method, &report);
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
  state.counters["runs"] = method == Method::kCentral   ? 1 + 2 * count
                           : method == Method::kAdjoint ? 2
                                                        : (count + kJetStride - 1) / kJetStride;
  if (method == Method::kAdjoint) state.counters["memory_mb"] = static_cast<double>(report.memory_bytes) / (1 << 20);
}

// One plain double simulation (what the ratios divide by), timed by the benchmark loop for reference.
void PlainSimulation(benchmark::State& state) {
  const Problem problem = MakeProblem(static_cast<int>(state.range(0)), 1);
  double seconds = 0.0;
  for (auto _ : state) seconds += TimePlainSimulation(problem);
  SetCounters(state, problem, seconds / static_cast<double>(state.iterations()));
}

// P = 1 ... 1000 on every model; the oracle up to 32
void Sizes(benchmark::internal::Benchmark* b, int largest) {
  b->ArgNames({"n", "P"});
  for (int n : {20, 200, kArm}) {
    for (int p : {1, 2, 4, 8, 16, 32, 100, 300, 1000}) {
      if (p <= largest) b->Args({n, p});
    }
  }
  b->Unit(benchmark::kMillisecond);
}
void AllSizes(benchmark::internal::Benchmark* b) { Sizes(b, 1000); }
void OracleSizes(benchmark::internal::Benchmark* b) { Sizes(b, 32); }

BENCHMARK(PlainSimulation)->ArgNames({"n", "P"})->Args({20, 1})->Args({200, 1})->Args({kArm, 1})->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(Gradient, implicit, Method::kImplicit)->Apply(AllSizes);
BENCHMARK_CAPTURE(Gradient, jet_factor, Method::kJetFactor)->Apply(OracleSizes);
BENCHMARK_CAPTURE(Gradient, central, Method::kCentral)->Apply(AllSizes);
BENCHMARK_CAPTURE(Gradient, adjoint, Method::kAdjoint)->Apply(AllSizes);

}  // namespace
}  // namespace tether::bench
