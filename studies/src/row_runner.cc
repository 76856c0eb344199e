#include "row_runner.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <deque>
#include <exception>
#include <future>
#include <map>
#include <mutex>
#include <sstream>
#include <thread>

#include "tether/dynamics/integration/default_gains.h"
#include "tether/dynamics/integration/integrator_descriptor.h"
#include "tether/dynamics/integration/interrupts.h"
#include "tether/dynamics/integration/simulator.h"
#include "tether/dynamics/io/csv_line.h"
#include "tether/dynamics/model/errors.h"
#include "tether/tuning/gain_objective.h"
#include "tether/tuning/gain_tuning.h"
#include "tether/tuning/reference.h"
#include "tether/tuning/task_threads.h"

namespace tether {
namespace {

std::string Number(double x) {
  if (std::isnan(x)) return "nan";
  std::ostringstream out;
  out.precision(17);
  out << x;
  return out.str();
}

std::string Line(const StudyRow& row) {
  std::string line;
  for (const nlohmann::json& v : row.values) line += CsvCell(CellText(v)) + ",";
  for (double m : row.metrics) line += Number(m) + ",";
  return line + CsvCell(row.status);
}

// Reference motions shared by the rows of one run, computed once per reference key by the first row that asks.
class ReferenceCache {
 public:
  std::shared_future<ReferenceMotion> Get(const RowScene& scene) {
    std::promise<ReferenceMotion> promise;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      const auto found = motions_.find(scene.reference_key);
      if (found != motions_.end()) return found->second;
      motions_[scene.reference_key] = promise.get_future().share();
    }
    try {
      promise.set_value(ComputeReference(scene.model));
    } catch (...) {
      promise.set_exception(std::current_exception());
    }
    std::lock_guard<std::mutex> lock(mutex_);
    return motions_[scene.reference_key];
  }

 private:
  std::mutex mutex_;
  std::map<std::string, std::shared_future<ReferenceMotion>> motions_;
};

StudyRow MeasureRow(const StudySpec& spec, int index, ReferenceCache* references, const RowMotion& motion) {
  StudyRow row;
  row.values = Combination(spec, index);
  row.metrics.assign(spec.metrics.size(), NAN);
  RowScene scene = SceneOfRow(spec, row.values, "row " + std::to_string(index));
  Trajectory<double> run;
  double seconds = 0.0;
  if (scene.tune_gains) {
    try {
      const TuneResult tuned = TuneGains(scene.model, TuneSettings{});
      scene.model = WithGains(scene.model, tuned.alpha, tuned.beta);
    } catch (const RunInterrupted&) {  // Ctrl-C in the Python module (interrupts.h): the row is not measured
      throw;
    } catch (const std::runtime_error& e) {  // InputError or SimulationDiverged: no gains to run with
      row.status = std::string("tuning failed: ") + e.what();
      return row;
    }
  }
  try {
    const auto begin = std::chrono::steady_clock::now();
    run = Record(scene.model);
    seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
  } catch (const SimulationDiverged& e) {
    row.status = std::string("diverged: ") + e.what();
    return row;
  }
  if (motion) motion(index, row.values, scene.model, run);
  double alpha = 0.0, beta = 0.0;
  GainsInUse(scene.model, &alpha, &beta);
  for (size_t m = 0; m < spec.metrics.size(); ++m) {
    const std::string& name = spec.metrics[m];
    if (name == "max_constraint_error") row.metrics[m] = run.LargestViolation();
    if (name == "energy_drift") row.metrics[m] = run.EnergyDrift();
    if (name == "seconds") row.metrics[m] = seconds;
    if (name == "seconds_per_simulated_second") row.metrics[m] = seconds / scene.model.simulation.duration;
    if (name == "alpha") row.metrics[m] = alpha;
    if (name == "beta") row.metrics[m] = beta;
    if (name == "events") row.metrics[m] = static_cast<double>(run.report.events.size());
    if (name == "rms_position_error") {
      try {
        row.metrics[m] = RmsPositionError(scene.model, references->Get(scene).get(), run);
      } catch (const SimulationDiverged& e) {
        row.status = std::string("reference diverged: ") + e.what();
      }
    }
  }
  // measured, but no longer the constrained motion: never "ok" (a weakly stabilized double pendulum ended 1 m
  // off with seven times its energy and was counted a stable run)
  if (row.status == "ok" && !run.report.drift.empty()) row.status = "drifted: " + run.report.drift;
  return row;
}

}  // namespace

double RowCost(const StudySpec& spec, int index) {
  const SimulationSettings& simulation = SceneOfRow(spec, Combination(spec, index), "row").model.simulation;
  return Describe(simulation.integrator).evaluations_per_step * static_cast<double>(StepCount(simulation));
}

void RunRows(const StudySpec& spec, const std::vector<int>& indices, int threads,
             const std::function<void(const FinishedRow&)>& on_row, const std::function<void()>& idle,
             const RowMotion& motion) {
  ReferenceCache references;
  std::atomic<size_t> next{0};
  std::atomic<bool> stop{false};
  std::mutex mutex;
  std::condition_variable ready;
  std::deque<FinishedRow> finished;
  std::exception_ptr failure;
  auto work = [&] {
    for (size_t k; !stop && !Interrupted() && (k = next++) < indices.size();) {
      try {
        FinishedRow row{indices[k], Line(MeasureRow(spec, indices[k], &references, motion))};
        std::lock_guard<std::mutex> lock(mutex);
        finished.push_back(std::move(row));
      } catch (...) {
        std::lock_guard<std::mutex> lock(mutex);
        if (!failure) failure = std::current_exception();
        stop = true;
      }
      ready.notify_one();
    }
  };
  const int workers = std::min(std::max(1, threads), static_cast<int>(indices.size()));
  std::vector<std::thread> pool = StartThreads(workers, work);
  if (pool.empty()) work();  // the system refused every thread (a process limit): the rows run on this one
  // the calling thread hands rows on as they come, until every row is in (or one failed)
  for (size_t handed = 0; handed < indices.size();) {
    if (Interrupted()) stop = true;
    std::unique_lock<std::mutex> lock(mutex);
    ready.wait_for(lock, std::chrono::milliseconds(10), [&] { return !finished.empty() || stop; });
    std::deque<FinishedRow> batch;
    batch.swap(finished);
    lock.unlock();
    for (const FinishedRow& row : batch) on_row(row);
    handed += batch.size();
    if (batch.empty() && stop) break;
    if (batch.empty()) idle();
  }
  for (std::thread& t : pool) t.join();
  for (const FinishedRow& row : finished) on_row(row);  // rows that were under way when the run stopped
  if (failure) std::rethrow_exception(failure);
  if (Interrupted()) throw StudyInterrupted(Interrupted());
}

}  // namespace tether
