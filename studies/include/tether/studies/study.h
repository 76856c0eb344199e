// Studies: run base scenes over the cartesian product of swept values (study_spec.h) and measure each run.
//
// Metrics of a row:
//   max_constraint_error           largest constraint violation over the run, m
//   rms_position_error             RMS distance from the reference motion (reference.h) over the step grid, m
//   energy_drift                   max |E - E0| / max(|E0|, 1 J)
//   seconds                        wall time of the run (the reference and any gain tuning excluded)
//   seconds_per_simulated_second   seconds / the scene's duration
//   alpha, beta                    the Baumgarte gains the run used (0 without Baumgarte; the default rule's when
//                                  the scene names none; the tuner's for "tuned")
//   events                         the joint limits' events of the run (impacts and releases, unilateral_events.h)
// A row whose run diverges, or whose gains cannot be tuned (the simulation diverges at every starting gain),
// gets NaN metrics and its message in `status`. Rows that differ only in integrator or
// stabilization share one reference motion.
//
// Rows run on `threads` threads and are written in row order, so the result does not depend on the thread
// count. The run is resumable: every finished row is appended at once to DIR/results.partial.csv, a new run of
// the same study (the same study file, scenes and binary: results_folder.h) reads it and skips those rows, and
// DIR/results.csv (written whole at the end, atomically) replaces it. study_mpi.h spreads the rows over MPI ranks with
// the same result.
#pragma once

#include <functional>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "tether/dynamics/integration/trajectory.h"
#include "tether/dynamics/model/errors.h"
#include "tether/studies/study_spec.h"

namespace tether {

struct StudyRow {
  std::vector<nlohmann::json> values;  // one per swept column
  std::vector<double> metrics;         // one per requested metric (NaN when the run diverged)
  std::string status = "ok";
};

// progress(done, total, seconds_left), called as rows finish.
using StudyProgress = std::function<void(int, int, double)>;

// What a study keeps of a row's motion besides its metrics (`tether study`'s index.html plays any row): called on
// the row's thread, before the row is handed on, with the row's index, its swept values, its model and its run,
// for every run that finished (a diverged run keeps no motion). Under MPI every rank calls it for its own rows.
using RowMotion = std::function<void(int index, const std::vector<nlohmann::json>& values, const Model<double>& model,
                                     const Trajectory<double>& run)>;

// A study stopped by a signal (interrupts.h) between rows: what finished is kept in the partial results, and
// running the study again resumes it.
class StudyInterrupted : public RunInterrupted {
 public:
  using RunInterrupted::RunInterrupted;
};

// What a study's results are the results of, as 16 hex digits: a hash (FNV-1a) of the study file, its scene
// files and the running binary. Partial results carry it, and a resume with any of them changed is refused.
std::string StudyFingerprint(const StudySpec& spec);

// Runs (or resumes) the study into `folder` on `threads` threads. Returns the rows in order and writes
// folder/results.csv. The partial results of a different study in `folder` are an InputError unless `restart`
// discards them; a study already finished there (results.fingerprint, results_folder.h) is read back, not run.
std::vector<StudyRow> RunStudy(const StudySpec& spec, const std::string& folder, int threads, bool restart,
                               const StudyProgress& progress, const RowMotion& motion = {});

}  // namespace tether
