// When fem-solve stops stepping to write something: the output times k·Δ_out, the
// checkpoint times (cadences k·Δ and a list), and the end time. Grid times are computed
// as k·Δ (never accumulated), and times closer than `time_tolerance` count as one stop,
// so that a run and its restart stop at exactly the same times.
#pragma once

#include <vector>

namespace slide::fem {

class OutputSchedule {
 public:
  /// Times closer than this (s) are the same stop.
  static constexpr double time_tolerance = 1e-9;

  /// `output_every` = 0: output at the checkpoint times only. Cadences ≤ 0 are ignored.
  OutputSchedule(double end_time, double output_every, std::vector<double> checkpoint_every,
                 std::vector<double> checkpoint_times);

  /// The first stop after `time` (never beyond the end time).
  double next_stop(double time) const;
  /// True when `time` is a checkpoint time (the end time is one).
  bool is_checkpoint(double time) const;
  double end_time() const { return end_time_; }

 private:
  double end_time_;
  double output_every_;
  std::vector<double> checkpoint_every_;
  std::vector<double> checkpoint_times_;
};

}  // namespace slide::fem
