// The output folder of a study while it runs: DIR/results.partial.csv holds a header ("index," + the results
// header) and one "INDEX,<line>" per finished row, appended and flushed as rows finish, so that an interrupted
// study resumes where it stopped; at the end DIR/results.csv is written whole (atomically), rows in order, and
// the partial file is removed.
#pragma once

#include <chrono>
#include <fstream>
#include <string>
#include <vector>

#include "row_runner.h"

namespace tether {

class ResultsFolder {
 public:
  // Creates the folder and takes up the rows an earlier run of the same study (same header) finished.
  ResultsFolder(const StudySpec& spec, const std::string& folder, const StudyProgress& progress);

  // Rows still to run, in order.
  std::vector<int> Unfinished() const;

  // Logs a finished row and reports progress.
  void Record(const FinishedRow& row);

  // Writes results.csv, removes the partial file and returns the rows. Every row must be finished.
  std::vector<StudyRow> Finish();

 private:
  const StudySpec& spec_;
  std::string folder_, header_;
  StudyProgress progress_;
  std::vector<std::string> lines_;  // per row; empty while unfinished
  std::ofstream log_;
  int done_ = 0, resumed_ = 0;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

}  // namespace tether
