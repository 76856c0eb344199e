// Interruptions (SIGINT, SIGTERM, SIGHUP) and the temporary files they must not leave behind.
//
// InstallInterruptHandlers(), called once by a program (the tether front end does), makes these signals remove
// every path that a TemporaryPath holds and then end the process as the signal would have (a shell reports
// 128 + the signal's number). Removal in the handler uses only unlink and rmdir, which are async-signal-safe:
// every registered file first, then every registered folder (emptied of the files registered in it).
//
// A job that can stop between pieces of work (a study between rows) holds a CatchInterrupts while it runs:
// the first signal then only sets Interrupted(), which the job polls; a second one ends the process as above.
// While a CancelRuns (below) is held, no SIGINT ends the process: an interpreter (Python) must outlive its runs.
#pragma once

#include <string>

namespace tether {

void InstallInterruptHandlers();

class TemporaryPath {
 public:
  TemporaryPath() = default;
  explicit TemporaryPath(const std::string& path);  // registers it (at most kMaxTemporaryPaths at a time)
  ~TemporaryPath();                                 // unregisters it; the path itself is the owner's to remove
  TemporaryPath(const TemporaryPath&) = delete;
  TemporaryPath& operator=(const TemporaryPath&) = delete;

 private:
  int slot_ = -1;
};
inline constexpr int kMaxTemporaryPaths = 64;

class CatchInterrupts {
 public:
  CatchInterrupts();
  ~CatchInterrupts();
  CatchInterrupts(const CatchInterrupts&) = delete;
  CatchInterrupts& operator=(const CatchInterrupts&) = delete;
};

// The signal caught while a CatchInterrupts was held (0: none).
int Interrupted();

// Removes the temporary paths and ends the process as `signal` would (after a signal that a child process took,
// while this one waited with it ignored).
[[noreturn]] void EndAsSignal(int signal);

// An interactive caller (the Python module, during one call) that wants a run to stop at once rather than at the
// end of a piece of work: while any CancelRuns is held, SIGINT is caught, and a run checks for it at every step
// and stops with RunInterrupted (errors.h); every run then held stops. When the last is released, the action it
// replaced (Python's) is back and a signal caught is forgotten. Holders may be in several threads.
class CancelRuns {
 public:
  CancelRuns();
  ~CancelRuns();
  CancelRuns(const CancelRuns&) = delete;
  CancelRuns& operator=(const CancelRuns&) = delete;

 private:
  CatchInterrupts catching_;
};

// Whether a run must stop now: a signal was caught while a CancelRuns is held.
bool RunsCancelled();

}  // namespace tether
