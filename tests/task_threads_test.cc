// StartThreads, RunTasks and IdleCores (tether/tuning/task_threads.h), which run fit's starts and, on the cores
// finished starts give back, the Jet runs of the Jacobians of the starts still running (and a study's rows):
//   - StartThreads starts as many threads as asked, each running the work once (none for a count of zero);
//   - every task runs exactly once, on as many threads as asked, and each thread gives its core back at the end;
//   - a task's exception is rethrown once all the other tasks have run;
//   - RunTasksOnIdleCores takes no more idle cores than it has tasks beyond the first, and gives them all back,
//     after an exception too.
#include "tether/tuning/task_threads.h"

#include <gtest/gtest.h>

#include <atomic>
#include <functional>
#include <mutex>
#include <set>
#include <stdexcept>
#include <thread>
#include <vector>

namespace tether {
namespace {

TEST(TaskThreads, StartThreadsStartsAsManyAsAskedEachRunningTheWorkOnce) {
  for (int count : {0, 1, 4}) {
    std::atomic<int> runs{0};
    std::vector<std::thread> pool = StartThreads(count, [&runs] { ++runs; });
    EXPECT_EQ(static_cast<int>(pool.size()), count);
    for (std::thread& t : pool) t.join();
    EXPECT_EQ(runs, count);
  }
}

TEST(TaskThreads, EveryTaskRunsOnceAndEachThreadGivesItsCoreBack) {
  std::vector<std::atomic<int>> runs(100);
  std::mutex mutex;
  std::set<std::thread::id> threads;
  std::vector<std::function<void()>> tasks;
  for (size_t i = 0; i < runs.size(); ++i) {
    tasks.push_back([&, i] {
      ++runs[i];
      std::lock_guard<std::mutex> lock(mutex);
      threads.insert(std::this_thread::get_id());
    });
  }
  IdleCores idle;
  RunTasks(tasks, 3, &idle);
  for (size_t i = 0; i < runs.size(); ++i) EXPECT_EQ(runs[i], 1) << i;
  EXPECT_LE(threads.size(), 3u);
  EXPECT_GE(threads.size(), 1u);
  EXPECT_EQ(idle.Take(10), 3);  // the three threads' cores
  EXPECT_EQ(idle.Take(10), 0);
}

TEST(TaskThreads, AnExceptionIsRethrownOnceTheOtherTasksHaveRun) {
  std::atomic<int> done{0};
  std::vector<std::function<void()>> tasks;
  for (int i = 0; i < 20; ++i) {
    tasks.push_back([&, i] {
      if (i == 3) throw std::runtime_error("task 3");
      ++done;
    });
  }
  EXPECT_THROW(RunTasks(tasks, 2, nullptr), std::runtime_error);
  EXPECT_EQ(done, 19);
}

TEST(TaskThreads, IdleCoresAreTakenAsTheTasksNeedAndGivenBack) {
  IdleCores idle;
  idle.Give(5);
  std::atomic<int> done{0};
  const std::vector<std::function<void()>> three(3, [&] { ++done; });
  RunTasksOnIdleCores(three, &idle);
  EXPECT_EQ(done, 3);
  EXPECT_EQ(idle.Take(10), 5);  // at most two taken, all given back
  idle.Give(5);
  const std::vector<std::function<void()>> failing(4, [] { throw std::runtime_error("diverged"); });
  EXPECT_THROW(RunTasksOnIdleCores(failing, &idle), std::runtime_error);
  EXPECT_EQ(idle.Take(10), 5);
  RunTasksOnIdleCores(three, nullptr);  // on the caller's thread alone
  EXPECT_EQ(done, 6);
}

}  // namespace
}  // namespace tether
