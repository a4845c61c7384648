// run::Plan: what a run of one stage does, resolved once, before anything is written, from
// the case, the command line and (on restart) the checkpoint: where the state comes from,
// when the run ends and stops to write, what it writes where. fem-solve and mpm-solve each
// resolve theirs (fem/fem_plan.hpp, mpm/mpm_plan.hpp) with their own typed settings
// beside it; run::execute (common/run/stage.hpp) carries it out.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "common/run/output_schedule.hpp"

namespace slide::run {

/// The options of the command line every stage has (each stage's options add theirs).
struct CommonOptions {
  std::filesystem::path output_dir;
  std::optional<double> until;                   ///< --until: end earlier than the case
  std::optional<std::filesystem::path> restart;  ///< --restart: a checkpoint of the stage
  bool write_vtk = true;                         ///< not --no-vtk
  /// --vtk-every: VTK frames every this many seconds (0: at every output step); none:
  /// the case's vtk_every, else automatic_vtk_every.
  std::optional<double> vtk_every;
  /// Read and check every input, then stop before the first file is written (the fuzz
  /// drivers, tests/fuzz/).
  bool inputs_only = false;
  /// Not --no-disk-check: a run whose outputs, estimated, would not fit on the output
  /// folder's disk is refused before it starts (run::check_output_volume).
  bool disk_check = true;
  /// --allow-changed: parts of the case a restart may find changed (case_fingerprint.hpp).
  std::vector<std::string> allow_changed;
};

/// Where a run's state comes from.
enum class Start {
  case_geometry,  ///< the case's mesh: fem-solve's geostatic stage, pure MPM
  particle_file,  ///< mpm-solve --particles: a transfer's particles, a new run from them
  restart,        ///< a checkpoint of the stage itself: the run continues
};

/// What a run writes where.
struct OutputPlan {
  std::filesystem::path folder;
  /// "fem" or "mpm": checkpoints are folder/<prefix>_t<T>.h5 (checkpoint_file_name).
  std::string checkpoint_prefix;
  bool write_vtk = true;
  double vtk_every = 0.0;  ///< s between frames (0: every output step)
  /// The end time is a checkpoint too (fem-solve: a later run continues from it).
  bool checkpoint_at_end = false;
  /// A fresh stage's first output is a checkpoint where the schedule has one (mpm-solve:
  /// mpm_t<t_T>.h5; fem-solve's start is fem_t0.000.h5 already, the geostatic state).
  bool checkpoint_at_start = false;
};

struct Plan {
  std::string case_name;
  Start start = Start::case_geometry;
  std::filesystem::path
      start_file;  ///< the particle file or checkpoint (Start::case_geometry: none)
  OutputSchedule schedule{0.0, 0.0, {}, {}};
  OutputPlan output;
  /// The files the run was made from (the case file, its mesh file): copied into the
  /// output folder's inputs/ with run.txt (program, version, start), so that a folder
  /// tells what made it.
  std::vector<std::filesystem::path> inputs;
  /// The run continues outputs an earlier run wrote (history rows and VTK frames up to
  /// its start are kept): a restart, except fem-solve's from its geostatic checkpoint.
  bool resume_outputs = false;
  /// Read and check every input, then stop before the first file is written (the fuzz
  /// drivers, tests/fuzz/).
  bool inputs_only = false;
  /// Refuse a run whose outputs would not fit on the disk (CommonOptions::disk_check).
  bool disk_check = true;

  double end_time() const { return schedule.end_time(); }
};

}  // namespace slide::run
