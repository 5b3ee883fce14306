// The diagnosis' two-thread helper (host_sim/diagnose/src/two_threads.hpp): every task exactly once, whatever the
// count and however unequal the tasks, on both threads, and a task's exception reaches the caller.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstddef>
#include <mutex>
#include <set>
#include <stdexcept>
#include <thread>
#include <vector>

#include "two_threads.hpp"

namespace {

using lashid::sim::detail::on_two_threads;

TEST(TwoThreads, RunsEveryTaskExactlyOnce) {
  for (std::size_t count : {0U, 1U, 2U, 3U, 1000U}) {
    SCOPED_TRACE(::testing::Message() << count << " tasks");
    std::vector<std::atomic<int>> runs(count);
    on_two_threads(count, [&](std::size_t i) { ++runs[i]; });
    for (std::size_t i = 0; i < count; ++i) EXPECT_EQ(runs[i].load(), 1) << "task " << i;
  }
}

TEST(TwoThreads, ShareUnequalTasksBetweenBothThreads) {
  // Task 0 holds its thread until the other thread has run every other task: this ends only if the tasks are
  // taken one at a time (a split into halves fixed in advance would hold task 0's half for good).
  constexpr std::size_t kCount = 8;
  std::atomic<std::size_t> others_done{0};
  std::mutex m;
  std::set<std::thread::id> threads;
  on_two_threads(kCount, [&](std::size_t i) {
    {
      const std::lock_guard<std::mutex> lock(m);
      threads.insert(std::this_thread::get_id());
    }
    if (i == 0) {
      const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(30);
      while (others_done.load() < kCount - 1 && std::chrono::steady_clock::now() < give_up) {
        std::this_thread::yield();
      }
    } else {
      ++others_done;
    }
  });
  EXPECT_EQ(others_done.load(), kCount - 1);
  EXPECT_EQ(threads.size(), 2U);
}

TEST(TwoThreads, PassesATasksExceptionToTheCaller) {
  std::atomic<int> runs{0};
  EXPECT_THROW(on_two_threads(50, [&](std::size_t i) {
                 ++runs;
                 if (i == 7) throw std::runtime_error("task 7");
               }),
               std::runtime_error);
  EXPECT_GE(runs.load(), 8);
}

}  // namespace
