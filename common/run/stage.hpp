// The run loop both stages share (fem-solve's failure stage, mpm-solve): stop at every
// time of the output schedule, write what is due there, end at the end time or when the
// stage says it is done (at rest). What a stage is made of, its fields, its time step,
// its files, stays with the stage; the loop, the schedule, the guard's energy check, the
// history format and the checkpoint names are here, once (common/run/README.md).
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "common/base/log.hpp"
#include "common/base/ranks.hpp"
#include "common/physics/material.hpp"
#include "common/run/output_schedule.hpp"
#include "common/run/plan.hpp"

namespace slide::run {

/// What execute asks a stage to write at one output step.
struct OutputStep {
  bool frame = false;  ///< a VTK frame
  /// A checkpoint of the current state to this file (empty: none).
  std::filesystem::path checkpoint;
};

/// What the summary line counts.
struct Work {
  std::int64_t steps = 0;   ///< steps this run took
  std::string unit;         ///< "element" or "particle"
  std::int64_t units = 0;   ///< how many of them
  double unit_steps = 0.0;  ///< Σ over the steps of the units that moved (the rate's numerator)
};

/// About what one output of a stage writes on this rank, bytes: the state a checkpoint
/// holds and a VTK frame shows (both are the stage's arrays, a frame about as large).
struct OutputSizes {
  double checkpoint = 0.0;
  double frame = 0.0;
};

/// The output a stage's start needs.
enum class StartOutput {
  none,   ///< none: the run continues outputs written already (a restart)
  row,    ///< an output like any stop's (a restart whose history lacks its time)
  first,  ///< the stage's first: a frame whatever the cadence, a checkpoint where the
          ///< schedule has one and the plan checkpoints the start
};

/// What the run lifecycle needs of a stage (fem-solve's explicit FE stage, mpm-solve).
class Stage {
 public:
  virtual ~Stage() = default;
  /// The time and step of the current state.
  virtual double time() const = 0;
  virtual std::int64_t step() const = 0;
  /// Opens the history, the VTK series and the stage's other outputs in the prepared
  /// output folder, keeping what an earlier run wrote up to now when `resume`.
  virtual void open_outputs(bool resume) = 0;
  /// Brings the state to the start of the loop (fem-solve's geostatic stage and the
  /// switch to the failure models, pure MPM's initial stresses, the guard's references),
  /// and says what output that start needs.
  virtual StartOutput start() = 0;
  /// Steps up to `stop` and lands on it exactly. False when the stage stopped earlier
  /// because it is done (a body at rest): the loop then writes that state and ends.
  virtual bool advance_to(double stop) = 0;
  /// The instability guard (docs/method.md §5): nothing when the state passes, else the
  /// diagnosis (which check, where). Collective on several ranks.
  virtual std::optional<std::string> check_stability() = 0;
  /// The history row, and what `step` asks for.
  virtual void write_output(const OutputStep& step) = 0;
  /// After the loop: the stage's last files and reports.
  virtual void finish() = 0;
  virtual Work work() const = 0;
  /// What one checkpoint and one frame write on this rank, about (run::check_output_volume).
  virtual OutputSizes output_sizes() const = 0;

  /// The last checkpoint written (or the one the run restarted from): what an
  /// instability's message names. Kept by execute.
  const std::filesystem::path& last_checkpoint() const { return last_checkpoint_; }

 protected:
  /// A checkpoint the stage wrote of its own (fem-solve's geostatic state, the zone exit).
  void note_checkpoint(const std::filesystem::path& file) { last_checkpoint_ = file; }

 private:
  friend struct Lifecycle;
  std::filesystem::path last_checkpoint_;
};

/// What a run did.
struct RunResult {
  Work work;
  double wall_seconds = 0.0;  ///< the start output and the loop (the slowest rank's)
  bool reached_end = true;    ///< false: the stage ended early (at rest)
};

/// Carries out `plan` with `stage`, the lifecycle every stage shares:
///   1. the output folder made, the temporaries of killed runs removed;
///   2. the stage's outputs opened (resumed on restart), its start, the start's output;
///   3. the loop: at every stop of the schedule the guard, then the output (the history
///      row, a VTK frame on the cadence, at the start, the checkpoints and, with
///      checkpoint_at_end, the end; a checkpoint where the schedule has one); a stage at
///      rest ends it;
///   4. the stage's finish, the wall time, the summary line.
/// A failed guard is an InstabilityError naming the check, the time and step, and the
/// last good checkpoint; nothing of that step is written. Collective on several ranks
/// (the root alone clears the folder and logs).
RunResult execute(Stage& stage, const Plan& plan, const Logger& log,
                  const Ranks& ranks = Ranks::single());

/// More checkpoints and VTK frames than a run may write: a million files in a folder is
/// already more than a file browser or ParaView's series lists; beyond it a cadence is a
/// slip, not a plan.
inline constexpr double max_output_files = 1e6;

/// Refuses, before anything is written, a run whose checkpoints and frames from `time`
/// to the end would be more than max_output_files files or more bytes than the disk of
/// the output folder has free (`sizes` summed over the ranks, each output at its largest:
/// every checkpoint, every output step a frame where the cadence says so): Error naming
/// the counts, the estimate and the space, with the cadence to change; else the estimate
/// in the log. Collective.
void check_output_volume(const Plan& plan, double time, OutputSizes sizes, const Logger& log,
                         const Ranks& ranks);

/// "fem_t2.000.h5": the checkpoint file name of a stage (`prefix` "fem" or "mpm") at
/// time t, three decimals (docs/contract.md).
std::string checkpoint_file_name(std::string_view prefix, double time);

/// More steps than a stage may take: 10⁹ steps of a 2000-element mesh are two days on
/// one core, of 32,000 particles a month; beyond it the step is a mistake, not a plan.
inline constexpr double max_steps = 1e9;

/// Refuses a run of `duration` s in steps of `dt` s that would take more than max_steps
/// steps (it would never end): Error naming the step count, dt and `cause` (what made
/// the step that small).
void check_step_count(double duration, double dt, std::string_view cause);

/// The resolution of the checkpoint names (three decimals of a second), s.
inline constexpr double checkpoint_name_resolution = 1e-3;

/// Refuses a checkpoint cadence the names cannot tell apart: 0 < `every` < 1 ms would
/// write several checkpoints under one name, each replacing the last (and a cadence of
/// 1e-12 s would never end). Error naming `what` (the key or option) otherwise.
void check_checkpoint_cadence(double every, std::string_view what);

/// Refuses checkpoint times (`times`, plus `also`, e.g. the geostatic state at t = 0)
/// that are different times with the same file name `prefix`_t<T>.h5. Error naming
/// `what` and the two times.
void check_checkpoint_times(std::vector<double> times, std::string_view prefix,
                            std::string_view what, std::vector<double> also = {});

/// At the start of a run: removes the temporaries killed runs left in `output_dir`, its
/// vtk/ and its inputs/ folders (remove_stale_temporaries), with one line saying how many.
void remove_temporaries_of_killed_runs(const std::filesystem::path& output_dir, const Logger& log);

/// On restart the materials must be the case's own: Error naming `source` and the first
/// difference (count, name, model or density) otherwise.
void check_restart_materials(const MaterialTable& from_checkpoint, const MaterialTable& from_case,
                             const std::string& source);

}  // namespace slide::run
