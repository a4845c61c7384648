#include "common/run/thread_tuner.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <numeric>
#include <string>
#include <utility>

namespace slide::run {

ThreadTuner::ThreadTuner(int requested, int cores, RunningTasks running, int period, int samples)
    : requested_(std::max(requested, 1)),
      cores_(std::max(cores, 1)),
      running_(std::move(running)),
      period_(std::max(period, 1)),
      samples_(static_cast<std::size_t>(std::max(samples, 1))),
      current_(requested_) {}

void ThreadTuner::record_step() {
  (current_ == requested_ ? steps_requested_ : steps_fewer_) += 1;
  if (requested_ == 1 || ++steps_since_sample_ < period_) return;
  steps_since_sample_ = 0;
  const std::optional<int> running = running_ ? running_() : std::nullopt;
  if (!running) return;
  others_.push_back(std::max(*running - 1, 0));  // this process's own thread is running
  if (others_.size() > samples_) others_.pop_front();
  const double others =
      std::accumulate(others_.begin(), others_.end(), 0.0) / static_cast<double>(others_.size());
  const int free_cores = static_cast<int>(std::lround(static_cast<double>(cores_) - others));
  current_ = std::clamp(free_cores, 1, requested_);
}

std::optional<int> ThreadTuner::procs_running() {
  std::ifstream in("/proc/stat");
  std::string key;
  while (in >> key) {
    if (key == "procs_running") {
      int n = 0;
      if (in >> n) return n;
      return std::nullopt;
    }
    in.ignore(1 << 20, '\n');
  }
  return std::nullopt;
}

}  // namespace slide::run
