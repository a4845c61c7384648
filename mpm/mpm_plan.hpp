// What an mpm-solve run does, resolved once from the case, the command line and the file
// it starts from (run::Plan, common/run/plan.hpp), before anything is read in full or
// written: the solver's settings with the command line's overrides, the case's [mpm]
// rules (time step, rest, speed bound, pure MPM's start), its materials and metrics,
// where the particles come from, when the run ends and what it writes. The one place
// where mpm-solve reads the case: the run itself (mpm_run.hpp) sees only the plan.
#pragma once

#include <filesystem>
#include <optional>
#include <string>

#include "common/base/log.hpp"
#include "common/geometry/mesh.hpp"
#include "common/run/plan.hpp"
#include "common/settings/fem_spec.hpp"
#include "common/settings/metrics_spec.hpp"
#include "common/settings/mpm_spec.hpp"
#include "mpm/mpm_record.hpp"
#include "mpm/mpm_solver.hpp"

namespace slide {
struct Case;  // common/input/case_file.hpp: only plan_mpm reads it
}  // namespace slide

namespace slide::mpm {

/// The command line's part of a run.
struct RunOptions : run::CommonOptions {
  std::optional<std::filesystem::path> particles_file;  ///< --particles
  /// --other-case: a particle file or checkpoint of another case is used (with a
  /// warning) instead of refused.
  bool other_case = false;
  std::optional<ShapeFunction> shape_function;  ///< overrides the case
  std::optional<UpdateScheme> update_scheme;    ///< overrides the case
  std::optional<int> sort_interval;             ///< overrides the default (benchmarks)
};

/// What the run needs of the case file.
struct MpmCase {
  std::string name;
  std::filesystem::path file;  ///< for messages
  MaterialTable materials;
  MpmSpec mpm;
  MetricsSpec metrics;
  /// Pure MPM: the body's mesh from the case geometry, and the case's base motion (a
  /// shaken case's pure MPM run is shaken too).
  std::optional<Mesh> body;
  std::optional<MotionSpec> motion;
};

struct MpmPlan {
  run::Plan run;
  MpmCase source;
  MpmSettings settings;  ///< the solver's: the case's with the command line's overrides
  bool other_case = false;
  /// A restart: the checkpoint's record, and the settings its run ran with.
  std::optional<MpmRecord> record;
  /// The parts of the case a restart must find unchanged (common/input/case_fingerprint.hpp),
  /// recorded in every checkpoint.
  SolverSettings fingerprint;
};

/// Resolves the plan of a run of `c` with `options` (reading the header of the file it
/// starts from); Error (one line) on options that cannot go together, a file of another
/// case (unless other_case), an end before the start or a restart at its end, checkpoint
/// names that would collide.
MpmPlan plan_mpm(const Case& c, const RunOptions& options, const Logger& log);

}  // namespace slide::mpm
