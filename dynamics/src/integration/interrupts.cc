#include "tether/dynamics/integration/interrupts.h"

#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <stdexcept>

namespace tether {
namespace {

constexpr size_t kMaxPathBytes = 4096;

enum SlotState { kFree, kClaimed, kReady };  // the handler reads only kReady slots
struct Slot {
  std::atomic<int> state{kFree};
  char path[kMaxPathBytes];
};
Slot slots[kMaxTemporaryPaths];
std::atomic<int> catching{0};
std::atomic<int> caught{0};
std::atomic<int> cancelling{0};  // CancelRuns held, changed under cancel_mutex
std::mutex cancel_mutex;
struct sigaction before_cancel;  // SIGINT's whole action (handler, flags, mask) before the first CancelRuns

// files first (unlink fails on a folder), then the folders they were in
void RemoveTemporaries() {
  for (Slot& slot : slots) {
    if (slot.state.load(std::memory_order_acquire) == kReady) ::unlink(slot.path);
  }
  for (Slot& slot : slots) {
    if (slot.state.load(std::memory_order_acquire) == kReady) ::rmdir(slot.path);
  }
}

extern "C" void OnInterrupt(int signal) {
  // noted, not the end: a first signal during a job, or any while runs in the Python module may be cancelled
  if (cancelling.load() > 0 || (catching.load() > 0 && caught.load() == 0)) {
    if (caught.load() == 0) caught.store(signal);
    return;
  }
  RemoveTemporaries();
  std::signal(signal, SIG_DFL);
  std::raise(signal);
}

}  // namespace

void EndAsSignal(int signal) {
  RemoveTemporaries();
  std::signal(signal, SIG_DFL);
  std::raise(signal);
  std::_Exit(128 + signal);  // a signal this process blocks
}

void InstallInterruptHandlers() {
  for (int signal : {SIGINT, SIGTERM, SIGHUP}) std::signal(signal, OnInterrupt);
}

TemporaryPath::TemporaryPath(const std::string& path) {
  if (path.size() >= kMaxPathBytes) throw std::length_error("TemporaryPath: path too long: " + path);
  for (int k = 0; k < kMaxTemporaryPaths; ++k) {
    int expected = kFree;
    if (!slots[k].state.compare_exchange_strong(expected, kClaimed)) continue;
    std::memcpy(slots[k].path, path.c_str(), path.size() + 1);
    slots[k].state.store(kReady, std::memory_order_release);
    slot_ = k;
    return;
  }
  throw std::length_error("TemporaryPath: more than " + std::to_string(kMaxTemporaryPaths) + " temporary paths");
}

TemporaryPath::~TemporaryPath() {
  if (slot_ >= 0) slots[slot_].state.store(kFree, std::memory_order_release);
}

CatchInterrupts::CatchInterrupts() { ++catching; }
CatchInterrupts::~CatchInterrupts() { --catching; }

int Interrupted() { return caught.load(); }

// The first holder installs the handler and the last puts the earlier action back, so that runs in several
// threads at once share one handler, and Python's action comes back exactly (its flags included).
CancelRuns::CancelRuns() {
  const std::lock_guard<std::mutex> lock(cancel_mutex);
  if (cancelling.fetch_add(1) > 0) return;
  caught.store(0);
  struct sigaction action = {};
  action.sa_handler = OnInterrupt;
  action.sa_flags = SA_RESTART;  // as std::signal installs it for the command line
  sigemptyset(&action.sa_mask);
  sigaction(SIGINT, &action, &before_cancel);
}

CancelRuns::~CancelRuns() {
  const std::lock_guard<std::mutex> lock(cancel_mutex);
  if (cancelling.fetch_sub(1) > 1) return;
  sigaction(SIGINT, &before_cancel, nullptr);
  caught.store(0);
}

bool RunsCancelled() {
  return cancelling.load(std::memory_order_relaxed) > 0 && caught.load(std::memory_order_relaxed) != 0;
}

}  // namespace tether
