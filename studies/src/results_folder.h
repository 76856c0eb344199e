// The output folder of a study while it runs.
//
// DIR/results.partial.csv holds the study's fingerprint ("# tether study FINGERPRINT"), a header ("index," +
// the results header) and one "INDEX,<line>" per finished row, appended and flushed as rows finish, so that an
// interrupted study resumes where it stopped. The fingerprint hashes the study file, its scene files and the
// running tether binary: partial results of anything else are refused (InputError naming --out) unless
// `restart` discards them. A line that is not whole (torn by a crash or a full disk) is dropped and its row run
// again. At the end DIR/results.csv is written whole (atomically), rows in order, DIR/results.fingerprint
// records what it is the result of, and the partial file is removed; a later run of the same study finds them
// and recomputes nothing (Done()). A results.csv that is not this study's (another fingerprint, or none: the
// results a repository ships) is never replaced without `restart`: InputError naming --out.
//
// Two studies never write into one folder at once: DIR/.lock is held (flock) while a ResultsFolder lives.
#pragma once

#include <chrono>
#include <fstream>
#include <string>
#include <vector>

#include "row_runner.h"

namespace tether {

// An exclusive flock on FOLDER/.lock for as long as it lives (InputError naming --out when another process
// holds it).
class FolderLock {
 public:
  explicit FolderLock(const std::string& folder);
  ~FolderLock();
  FolderLock(const FolderLock&) = delete;
  FolderLock& operator=(const FolderLock&) = delete;

 private:
  int descriptor_ = -1;
};

class ResultsFolder {
 public:
  // Creates the folder, locks it and takes up the rows an earlier run of the same study finished.
  ResultsFolder(const StudySpec& spec, const std::string& folder, bool restart, const StudyProgress& progress);

  // Whether results.csv already holds this very study (nothing to run; Finish() reads it back).
  bool Done() const { return done_already_; }

  // Rows still to run, in order.
  std::vector<int> Unfinished() const;

  // Logs a finished row and reports progress.
  void Record(const FinishedRow& row);

  // Rows finished so far, of how many.
  int finished() const { return done_; }
  int total() const { return static_cast<int>(lines_.size()); }

  // Writes results.csv, removes the partial file and returns the rows. Every row must be finished.
  std::vector<StudyRow> Finish();

 private:
  void TakeUpPartial(bool restart);
  void WritePartial();

  const StudySpec& spec_;
  std::string folder_;
  FolderLock lock_;
  std::string header_, fingerprint_;
  StudyProgress progress_;
  std::vector<std::string> lines_;  // per row; empty while unfinished
  std::vector<double> cost_;        // per row, the expected relative cost (RowCost)
  double cost_done_ = 0.0, cost_resumed_ = 0.0, cost_total_ = 0.0;
  std::ofstream log_;
  int done_ = 0;
  bool done_already_ = false;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

}  // namespace tether
