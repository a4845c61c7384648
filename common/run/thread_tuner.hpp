// The OpenMP thread count for a stage's next step: the requested count, or fewer when
// other processes hold the machine's cores. The MPM kernels' results do not depend on
// the count (mpm/README.md, "Threads on a shared machine"), so it may change between
// any two steps. Each of a step's barriers waits for the slowest thread, and a thread
// that shares its core with a busy process is parked for whole timeslices: column-short
// with a busy process on each of the 2 cores took 23–24.5 s on 2 threads, 14.5–16.8 s
// on 1. Every `period` steps the tuner reads how many tasks the kernel runs
// (/proc/stat, procs_running, taken between steps, when this process runs one thread),
// averages the others over the last `samples` readings, and runs min(requested, cores −
// others, rounded) threads, at least one. Where /proc/stat cannot be read it keeps the
// requested count.
#pragma once

#include <cstddef>
#include <deque>
#include <functional>
#include <optional>

namespace slide::run {

class ThreadTuner {
 public:
  /// Tasks running on the machine now, this process's included (procs_running), or
  /// nothing when not known.
  using RunningTasks = std::function<std::optional<int>()>;
  /// `requested` threads (≥ 1; 1: no tuning) on a machine of `cores` processors (all of
  /// them, as procs_running counts all their tasks).
  ThreadTuner(int requested, int cores, RunningTasks running = procs_running, int period = 10,
              int samples = 8);

  /// The count for the next step.
  int threads() const { return current_; }
  int requested() const { return requested_; }
  /// One step ran with threads().
  void record_step();

  /// Steps run so far with the requested count and with fewer.
  std::size_t steps_requested() const { return steps_requested_; }
  std::size_t steps_fewer() const { return steps_fewer_; }

  /// /proc/stat's procs_running.
  static std::optional<int> procs_running();

 private:
  int requested_;
  int cores_;
  RunningTasks running_;
  int period_;
  std::size_t samples_;
  int current_;
  int steps_since_sample_ = 0;
  std::deque<int> others_;  ///< the other tasks at the last readings
  std::size_t steps_requested_ = 0, steps_fewer_ = 0;
};

}  // namespace slide::run
