// When a stage stops stepping to write something: the output times k·Δ_out, the
// checkpoint times (cadences k·Δ and a list), and the end time. Grid times are computed
// as k·Δ (never accumulated), and times closer than `tolerance(t)` count as one stop, so
// that a run and its restart stop at exactly the same times. fem-solve and mpm-solve
// share this schedule (common/run/README.md).
#pragma once

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <string_view>
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

  /// At most how many checkpoints and output steps the schedule has after `time` (a
  /// closed form, not a walk: the bound is checked before a run writes, for any cadence).
  double checkpoints_after(double time) const;
  double outputs_after(double time) const;

  /// `time` is k·`every` for some integer k (within the tolerance); false for every ≤ 0.
  static bool on_grid(double time, double every);

 private:
  double end_time_;
  double output_every_;
  std::vector<double> checkpoint_every_;
  std::vector<double> checkpoint_times_;
};

/// The VTK frames a stage makes when neither the case file (vtk_every) nor the command
/// line (--vtk-every) sets a cadence: about this many per stage.
inline constexpr int automatic_vtk_frames = 100;

/// That cadence, s: the smallest whole multiple of `output_every` that makes at most
/// automatic_vtk_frames frames between `start` and `end` (frames are written at output
/// steps), or 0, a frame at every output step, when output_every is 0 (the outputs are
/// then the checkpoints, few already).
double automatic_vtk_every(double start, double end, double output_every);

/// Refuses a VTK cadence `every` (named `what`, e.g. "--vtk-every") that is not a whole
/// multiple of `output_every` when both are > 0: frames are written at output steps, and
/// would then land on few of them.
void check_vtk_every(double every, double output_every, std::string_view what);

/// A stage's VTK cadence, s: --vtk-every (`option`, checked here), else the case file's
/// vtk_every (checked by the case reader), else automatic_vtk_every from the stage's
/// `start` to its `end`.
double choose_vtk_every(std::optional<double> option, std::optional<double> case_value,
                        double start, double end, double output_every);

/// The cadence for the log: "every 0.2 s", or "at every output step" for 0.
std::string describe_vtk_every(double every);

/// Whether the output step at `time` writes a VTK frame: always at the stage's start, its
/// checkpoints and its end, else on the grid k·`vtk_every` (every step for 0).
inline bool is_vtk_frame(double time, double vtk_every, bool start_checkpoint_or_end) {
  return start_checkpoint_or_end || vtk_every <= 0.0 || OutputSchedule::on_grid(time, vtk_every);
}

}  // namespace slide::run
