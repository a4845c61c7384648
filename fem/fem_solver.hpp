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
#include "fem/explicit_stage.hpp"
#include "fem/fem_plan.hpp"

namespace slide::fem {

/// Runs the FE phase as `plan` says (fem_plan.hpp): the stage (explicit_stage.hpp) handed
/// to the shared run lifecycle (run::execute: outputs, the guard, the loop, the summary
/// line). Throws Error (one line) on bad input, on an instability and on an element
/// inversion in updated Lagrangian mode; checkpoints already written stay as they are
/// and no partial one is left.
FemRunSummary run_fem(const FemPlan& plan, const Logger& log);

}  // namespace slide::fem
