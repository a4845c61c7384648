// When a stage stops stepping to write something: the output times k·Δ_out, the
// checkpoint times (cadences k·Δ and a list), and the end time. Grid times are computed
// as k·Δ (never accumulated), and times closer than `tolerance(t)` count as one stop, so
// that a run and its restart stop at exactly the same times. fem-solve and mpm-solve
// share this schedule (common/run/README.md).
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

namespace slide::run {

class OutputSchedule {
 public:
  /// Times closer than this (s) are the same stop: 10⁻⁹ of the time, at least 10⁻⁹ s.
  static double tolerance(double time) { return 1e-9 * std::max(1.0, std::abs(time)); }

  /// `output_every` = 0: output at the checkpoint times only. Cadences ≤ 0 are ignored.
  OutputSchedule(double end_time, double output_every, std::vector<double> checkpoint_every,
                 std::vector<double> checkpoint_times);

  /// The first stop after `time` (never beyond the end time).
  double next_stop(double time) const;
  /// True when `time` is on a checkpoint cadence or in the checkpoint list (the end time
  /// only when it is one of those: each stage decides what it writes at its end).
  bool is_checkpoint(double time) const;
  /// True when a history row is due at `time`: the output grid, a checkpoint, the end.
  bool is_output(double time) const;
  /// True at (or within the tolerance of) the end time.
  bool is_end(double time) const { return end_time_ - time <= tolerance(end_time_); }
  double end_time() const { return end_time_; }

  /// `time` is k·`every` for some integer k (within the tolerance); false for every ≤ 0.
  static bool on_grid(double time, double every);

 private:
  double end_time_;
  double output_every_;
  std::vector<double> checkpoint_every_;
  std::vector<double> checkpoint_times_;
};

}  // namespace slide::run
