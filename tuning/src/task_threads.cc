#include "tether/tuning/task_threads.h"

#include <algorithm>
#include <atomic>
#include <exception>
#include <system_error>
#include <thread>

namespace tether {

void IdleCores::Give(int cores) {
  std::lock_guard<std::mutex> lock(mutex_);
  idle_ += cores;
}

int IdleCores::Take(int wanted) {
  std::lock_guard<std::mutex> lock(mutex_);
  const int taken = std::clamp(wanted, 0, idle_);
  idle_ -= taken;
  return taken;
}

std::vector<std::thread> StartThreads(int count, const std::function<void()>& work) {
  std::vector<std::thread> pool;
  try {
    for (int t = 0; t < count; ++t) pool.emplace_back(work);
  } catch (const std::system_error&) {
    // refused: the work runs on those that did start
  }
  return pool;
}

void RunTasks(const std::vector<std::function<void()>>& tasks, int threads, IdleCores* idle) {
  std::atomic<size_t> next{0};
  std::exception_ptr error;
  std::mutex error_mutex;
  const auto work = [&] {
    for (size_t i = next++; i < tasks.size(); i = next++) {
      try {
        tasks[i]();
      } catch (...) {
        std::lock_guard<std::mutex> lock(error_mutex);
        if (!error) error = std::current_exception();
      }
    }
    if (idle) idle->Give(1);
  };
  std::vector<std::thread> pool = StartThreads(threads - 1, work);
  work();  // on this thread too, so that the tasks run where the system refused every thread
  for (std::thread& t : pool) t.join();
  if (error) std::rethrow_exception(error);
}

void RunTasksOnIdleCores(const std::vector<std::function<void()>>& tasks, IdleCores* idle) {
  const int taken = idle ? idle->Take(static_cast<int>(tasks.size()) - 1) : 0;
  try {
    RunTasks(tasks, 1 + taken, nullptr);
  } catch (...) {
    if (idle) idle->Give(taken);
    throw;
  }
  if (idle) idle->Give(taken);
}

}  // namespace tether
