// The FE phase driver (docs/method.md §3): geostatic stage, switch to the failure models,
// explicit failure stage with outputs, checkpoints, mesh quality and the instability
// guard; or the continuation of a run from one of its checkpoints.
//
// Output cadence: the run stops exactly (the last step before a stop is shortened) at
// every output time k·fem.output_every, every checkpoint time (k·fem.checkpoint_every,
// k·--checkpoint-every, the listed fem.checkpoint_times) and the end time; times within
// 1 ns count as one. At every stop: instability guard, one fem_history.csv row, the VTK
// frame when the stop is on the VTK cadence (the start, the checkpoints and the end
// always are), and the checkpoint when the stop is a checkpoint time. Because steps land on
// the stops and a step depends only on the stored state, a run restarted from any
// checkpoint reproduces the continuous run bit for bit.
#pragma once

#include <filesystem>
#include <optional>
#include <vector>

#include "common/base/log.hpp"
#include "common/input/case_file.hpp"

namespace slide::fem {

struct FemOptions {
  std::filesystem::path output_dir;
  std::optional<double> until;                   ///< end time instead of fem.end_time
  std::optional<std::filesystem::path> restart;  ///< a kind "fem" checkpoint
  double checkpoint_every = 0.0;                 ///< extra checkpoint cadence, s (0: none)
  bool checkpoint_at_zone_exit = false;
  bool write_vtk = true;
  /// --vtk-every: VTK frames every this many seconds (0: at every output step); none:
  /// the case's fem.vtk_every, else run::automatic_vtk_every.
  std::optional<double> vtk_every;
  std::optional<ElementType> element;    ///< overrides mesh.element
  std::optional<Kinematics> kinematics;  ///< overrides fem.kinematics
  /// Read and check the case and the mesh, or the restart checkpoint, then return before
  /// the first file is written (the fuzz drivers, tests/fuzz/).
  bool inputs_only = false;
};

struct FemRunSummary {
  Index steps = 0;  ///< time steps taken by this run
  Index elements = 0;
  double wall_seconds = 0.0;
  double end_time = 0.0;
  /// From the whole history (including the rows before a restart):
  std::optional<double> last_time_in_zone;  ///< last output time inside the zone
  std::optional<double> zone_exit_time;     ///< first output time outside it
  /// First output time with an inverted element (is_inverted: det J < 0 at a corner, or zero area).
  std::optional<double> first_time_inverted;
  std::optional<double> first_time_jacobian_ratio_negative;  ///< (|J_t|/|J_0|)_min < 0
  double ke_over_pe0_max = 0.0;
  double ke_over_pe0_max_time = 0.0;
  std::vector<std::filesystem::path> checkpoints;  ///< written by this run
};

/// Runs the FE phase of `c`. Throws Error (one line) on bad input, on an instability
/// and on an element inversion in updated Lagrangian mode; checkpoints already written
/// stay as they are and no partial one is left.
FemRunSummary run_fem(const Case& c, const FemOptions& options, const Logger& logger);

}  // namespace slide::fem
