// Instructions retired by the calling thread over a stretch of code, from the
// CPU's hardware counter through Linux's perf_event_open, for the benchmarks' figures per
// particle-step and element-step: instruction counts, unlike seconds, do not change with
// the machine's load. Virtual machines often hide the counter (perf_event_open fails,
// ENOENT or EOPNOTSUPP): then `available()` is false and the benchmarks say so and point
// to tools/benchmarks/instructions.sh, which counts the same under callgrind.
#pragma once

#include <cstdint>
#include <cstring>
#include <optional>

#include <linux/perf_event.h>
#include <sys/ioctl.h>
#include <sys/syscall.h>
#include <sys/types.h>
#include <unistd.h>

namespace slide::bench {

class InstructionCounter {
 public:
  /// Opens the counter of the calling thread: the benchmarks count their 1-thread runs,
  /// where OpenMP runs every parallel region on it (a pool's threads would add their
  /// counts only when they exit).
  InstructionCounter() {
    perf_event_attr attr;
    std::memset(&attr, 0, sizeof(attr));
    attr.type = PERF_TYPE_HARDWARE;
    attr.size = sizeof(attr);
    attr.config = PERF_COUNT_HW_INSTRUCTIONS;
    attr.disabled = 1;
    attr.exclude_kernel = 1;
    attr.exclude_hv = 1;
    descriptor_ = static_cast<int>(syscall(SYS_perf_event_open, &attr, 0, -1, -1, 0));
  }
  ~InstructionCounter() {
    if (descriptor_ >= 0) close(descriptor_);
  }
  InstructionCounter(const InstructionCounter&) = delete;
  InstructionCounter& operator=(const InstructionCounter&) = delete;

  bool available() const { return descriptor_ >= 0; }
  void start() {
    if (!available()) return;
    ioctl(descriptor_, PERF_EVENT_IOC_RESET, 0);
    ioctl(descriptor_, PERF_EVENT_IOC_ENABLE, 0);
  }
  /// The instructions since start(), none without a counter.
  std::optional<double> stop() {
    if (!available()) return std::nullopt;
    ioctl(descriptor_, PERF_EVENT_IOC_DISABLE, 0);
    std::uint64_t count = 0;
    if (read(descriptor_, &count, sizeof(count)) != static_cast<ssize_t>(sizeof(count))) {
      return std::nullopt;
    }
    return static_cast<double>(count);
  }

 private:
  int descriptor_ = -1;
};

}  // namespace slide::bench
