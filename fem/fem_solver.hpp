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
#include "common/base/types.hpp"
#include "fem/fem_plan.hpp"

namespace slide::fem {

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

/// Runs the FE phase as `plan` says (fem_plan.hpp): the stage (explicit_stage.hpp) handed
/// to the shared run lifecycle (run::execute: outputs, the guard, the loop, the summary
/// line). Throws Error (one line) on bad input, on an instability and on an element
/// inversion in updated Lagrangian mode; checkpoints already written stay as they are
/// and no partial one is left.
FemRunSummary run_fem(const FemPlan& plan, const Logger& log);

}  // namespace slide::fem
