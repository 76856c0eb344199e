// Studies: run a base scene over the cartesian product of swept values and measure each run.
//
// STUDY.json (CONTRACT.md): {"scene": path relative to STUDY.json, "sweep": {PTR: [values], ...},
// "metrics": [names]}. A row is one combination, the first swept pointer varying slowest, in the order the
// file writes them; each value is written into the scene at its JSON Pointer (integrator names included) and the
// scene is read again with the usual validation. Metrics:
//   max_constraint_error   largest constraint violation over the run, m
//   rms_position_error     RMS distance from the reference motion (reference.h) over the step grid, m
//   energy_drift           max |E - E0| / max(|E0|, 1 J)
//   seconds                wall time of the run (the reference excluded)
// A row whose run diverges gets NaN metrics and its message in `status`.
//
// Rows run on `threads` threads and are written in row order, so the result does not depend on the thread
// count. The run is resumable: every finished row is appended at once to DIR/results.partial.csv, a new run of
// the same study reads it and skips those rows, and DIR/results.csv (written whole at the end, atomically)
// replaces it.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace tether {

struct StudySpec {
  std::string path;                     // STUDY.json, for messages
  std::string scene_path;               // resolved against STUDY.json's folder
  nlohmann::json scene;                 // the base scene document
  std::vector<std::string> pointers;    // swept, in the file's order
  std::vector<std::vector<nlohmann::json>> values;  // per pointer
  std::vector<std::string> metrics;
};

// Reads and validates STUDY.json (and that its scene exists and is valid). Throws InputError.
StudySpec ReadStudySpec(const std::string& path);

struct StudyRow {
  std::vector<nlohmann::json> values;  // one per swept pointer
  std::vector<double> metrics;         // one per requested metric (NaN when the run diverged)
  std::string status = "ok";
};

int RowCount(const StudySpec& spec);

// Runs (or resumes) the study into `folder`; `progress(done, total, eta_seconds)` is called as rows finish.
// Returns the rows in order and writes folder/results.csv.
std::vector<StudyRow> RunStudy(const StudySpec& spec, const std::string& folder, int threads,
                               const std::function<void(int, int, double)>& progress);

}  // namespace tether
