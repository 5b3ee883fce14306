// Work shared by the calling thread and one more (the diagnosis' parallelism; docs/diagnose.md "Time").
//
// Each task writes only its own result, so the answers do not depend on which thread ran which task or when: a
// diagnosis is the same as on one thread, bit for bit. Two threads because the machines this runs on have two
// cores and the candidates of a round already run side by side (candidates_for).
#pragma once

#include <atomic>
#include <cstddef>
#include <future>

namespace lashid::sim::detail {

/// task(i) for every i in [0, count): each thread takes the next index as it finishes one, so tasks of unequal
/// cost (a backlash's regime iteration takes one to nine passes) keep both threads busy to the end.
template <class Task>
void on_two_threads(std::size_t count, Task task) {
  std::atomic<std::size_t> next{0};
  const auto work = [&] {
    for (std::size_t i = next++; i < count; i = next++) task(i);
  };
  auto other = std::async(std::launch::async, work);
  work();
  other.get();
}

}  // namespace lashid::sim::detail
