#include "tether/dynamics/interrupts.h"

#include <unistd.h>

#include <atomic>
#include <csignal>
#include <cstring>
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
  if (catching.load() > 0 && caught.load() == 0) {
    caught.store(signal);
    return;
  }
  RemoveTemporaries();
  std::signal(signal, SIG_DFL);
  std::raise(signal);
}

}  // namespace

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

}  // namespace tether
