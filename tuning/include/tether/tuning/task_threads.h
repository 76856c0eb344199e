// Running independent tasks on the cores: fit's starts (trajectory_fit.cc), and within a start the Jet runs of a
// Jacobian (shooting_problem.cc) on the cores that starts have left idle; a study's rows (studies' row_runner.cc)
// start their threads here too. Near the end of a batch of starts fewer starts are left than cores; the last
// start's Jacobians then take up the cores the finished ones gave back (on the acrobot's tip-height swing-up the
// fit's CPU use rose from 172% to 191% of its wall time, which fell from 17.6 to 15.5 s).
#pragma once

#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace tether {

// A count of cores that no task is using: given by a thread that found no task left, taken by work that can
// spread over more threads.
class IdleCores {
 public:
  void Give(int cores);
  // Up to `wanted` cores (none where wanted <= 0).
  int Take(int wanted);

 private:
  std::mutex mutex_;
  int idle_ = 0;
};

// Up to `count` threads running `work`: fewer where the system refuses one (a process limit on threads), those that
// did start (a joinable thread left behind by the exception would abort the process). The caller joins them.
std::vector<std::thread> StartThreads(int count, const std::function<void()>& work);

// Runs every task on up to `threads` threads, the caller's among them, each taking the next task left. A thread
// that finds none left gives its core to `idle` (when not null). Once all have finished, the first exception a task
// threw is rethrown. Where the system refuses a thread, the tasks run on those that did start.
void RunTasks(const std::vector<std::function<void()>>& tasks, int threads, IdleCores* idle);

// The same on the caller's thread and as many of `idle`'s cores as there are tasks beyond the first (all on the
// caller's thread where idle is null), the cores given back after.
void RunTasksOnIdleCores(const std::vector<std::function<void()>>& tasks, IdleCores* idle);

}  // namespace tether
