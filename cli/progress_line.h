// The progress of a long optimization (identify, fit, tune) on stderr, so that a fit of a minute is not a minute
// of silence. On a terminal: one line redrawn in place, from one second on, at most four times a second, with the
// evaluations so far, the smallest cost among them and the time; erased when the work ends. Elsewhere (a log
// file, CI): a plain line every ten seconds from ten seconds on, so that short runs print nothing. --quiet hides
// it. Evaluations may come from several threads (a fit's starts).
#pragma once

#include <chrono>
#include <mutex>
#include <string>

#include "tether/tuning/optimizer.h"

namespace tether::cli {

class ProgressLine {
 public:
  // `what` names the work ("identify"); nothing is shown when `quiet`.
  ProgressLine(std::string what, bool quiet);
  ~ProgressLine();  // erases the line on a terminal
  ProgressLine(const ProgressLine&) = delete;
  ProgressLine& operator=(const ProgressLine&) = delete;

  // The optimizer's hook (OptimizerSettings::observer); empty when quiet.
  EvaluationObserver Observer();

 private:
  void Evaluated(double cost);

  const std::string what_;
  const bool quiet_, terminal_;
  const std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
  std::mutex mutex_;
  long evaluations_ = 0;
  double best_;
  double last_shown_ = 0.0;  // seconds after start_
  bool drawn_ = false;       // a line is on the terminal
};

}  // namespace tether::cli
