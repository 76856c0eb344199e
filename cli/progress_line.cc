#include "progress_line.h"

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <limits>

namespace tether::cli {
namespace {

constexpr double kTerminalFirst = 1.0, kTerminalEvery = 0.25;  // seconds
constexpr double kLogFirst = 10.0, kLogEvery = 10.0;

}  // namespace

ProgressLine::ProgressLine(std::string what, bool quiet)
    : what_(std::move(what)),
      quiet_(quiet),
      terminal_(::isatty(STDERR_FILENO) != 0),
      best_(std::numeric_limits<double>::infinity()) {}

ProgressLine::~ProgressLine() {
  if (drawn_) std::fprintf(stderr, "\r\033[K");
}

EvaluationObserver ProgressLine::Observer() {
  if (quiet_) return nullptr;
  return [this](double cost) { Evaluated(cost); };
}

void ProgressLine::Evaluated(double cost) {
  std::lock_guard<std::mutex> lock(mutex_);
  ++evaluations_;
  if (std::isfinite(cost) && cost < best_) best_ = cost;
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const double first = terminal_ ? kTerminalFirst : kLogFirst, every = terminal_ ? kTerminalEvery : kLogEvery;
  if (seconds < first || (last_shown_ > 0.0 && seconds - last_shown_ < every)) return;
  last_shown_ = seconds;
  std::fprintf(stderr, "%stether: %s: %ld evaluations, smallest cost %.6g, %.0f s%s", terminal_ ? "\r" : "",
               what_.c_str(), evaluations_, best_, seconds, terminal_ ? "\033[K" : "\n");
  std::fflush(stderr);
  drawn_ = terminal_;
}

}  // namespace tether::cli
