// The run loop both stages share (fem-solve's failure stage, mpm-solve): stop at every
// time of the output schedule, write what is due there, end at the end time or when the
// stage says it is done (at rest). What a stage is made of, its fields, its time step,
// its files, stays with the stage; the loop, the schedule, the guard's energy check, the
// history format and the checkpoint names are here, once (common/run/README.md).
#pragma once

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "common/base/log.hpp"
#include "common/physics/material.hpp"
#include "common/run/output_schedule.hpp"

namespace slide::run {

/// What the loop needs of a stage.
class Stage {
 public:
  virtual ~Stage() = default;
  /// The time of the current state, s.
  virtual double time() const = 0;
  /// Steps up to `stop` and lands on it exactly. False when the stage stopped earlier
  /// because it is done (a body at rest): the loop then writes that state and ends.
  virtual bool advance_to(double stop) = 0;
  /// Checks the state (the instability guard; InstabilityError) and writes the history
  /// row, the VTK frame and, when `checkpoint`, a checkpoint of the current state.
  virtual void write_output(bool checkpoint) = 0;
};

/// Runs `stage` from its time to the schedule's end: at every stop of the schedule it
/// writes the output, with a checkpoint where the schedule has one (and at the end when
/// `checkpoint_at_end`). Returns false when the stage ended early (at rest).
bool drive(Stage& stage, const OutputSchedule& schedule, bool checkpoint_at_end);

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

/// At the start of a run: removes the temporaries killed runs left in `output_dir` and
/// its vtk/ folder (remove_stale_temporaries), with one line saying how many.
void remove_temporaries_of_killed_runs(const std::filesystem::path& output_dir, const Logger& log);

/// On restart the materials must be the case's own: Error naming `source` and the first
/// difference (count, name, model or density) otherwise.
void check_restart_materials(const MaterialTable& from_checkpoint, const MaterialTable& from_case,
                             const std::string& source);

}  // namespace slide::run
