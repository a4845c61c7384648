// What a fem-solve run does, resolved once from the case, the command line and (on
// restart) the checkpoint (run::Plan, common/run/plan.hpp), before the first file is
// written: the mesh (the case's, or the checkpoint's), the case's FE settings with the
// command line's overrides, the materials and gravity, the state a restart continues and
// its restart record, when the run ends and what it writes. The one place where fem-solve
// reads the case: the run itself (fem_solver.hpp) sees only the plan.
#pragma once

#include <filesystem>
#include <optional>
#include <string>

#include "common/base/log.hpp"
#include "common/geometry/mesh.hpp"
#include "common/io/checkpoint.hpp"
#include "common/physics/material.hpp"
#include "common/run/plan.hpp"
#include "common/run/restart_record.hpp"
#include "common/settings/fem_spec.hpp"

namespace slide {
struct Case;  // common/input/case_file.hpp: only plan_fem reads it
}  // namespace slide

namespace slide::fem {

/// The command line's part of a run.
struct FemOptions : run::CommonOptions {
  double checkpoint_every = 0.0;  ///< extra checkpoint cadence, s (0: none)
  bool checkpoint_at_zone_exit = false;
  std::optional<ElementType> element;    ///< overrides mesh.element
  std::optional<Kinematics> kinematics;  ///< overrides fem.kinematics
};

/// The stages of fem-solve, as its checkpoints' restart records name them.
inline constexpr const char* geostatic_stage = "geostatic";
inline constexpr const char* failure_stage = "failure";

/// The restart record of a kind "fem" checkpoint (common/run/restart_record.hpp): the
/// stage, the guard's references, and the settings the state was computed with.
struct FemRecord : run::RunRecord {
  std::string kinematics;
  std::string element_type;
  double courant = 0.0;
  double time_step = 0.0;  ///< the step the state would take next, s
  double hourglass_coefficient = 0.0;
};
SolverSettings write_record(const FemRecord& record);
/// Error naming `source` and the key when an entry is missing, of the wrong type or out
/// of range, or the stage is neither "geostatic" nor "failure".
FemRecord read_record(const SolverSettings& settings, const std::string& source);

/// What the run needs of the case file.
struct FemCase {
  std::string name;
  std::filesystem::path file;  ///< for messages
  MaterialTable materials;
  Vec2 gravity = gravity_vector();
  FemSpec fem;  ///< with the command line's kinematics
  /// The latest time on the run's clock a phase of the case shakes to (this run's end,
  /// the case's mpm.end_time): the motion's samples are kept up to it and checkpointed
  /// for mpm-solve, not a record's whole length.
  double motion_until = 0.0;
};

struct FemPlan {
  run::Plan run;
  FemCase source;
  /// The mesh: the case's (fresh), the checkpoint's (restart), with its element type.
  Mesh mesh;
  /// Restart: the state the run continues and its record (the mesh moved out of it).
  std::optional<FemCheckpoint> restart;
  FemRecord record;
  /// The parts of the case a restart must find unchanged (common/input/case_fingerprint.hpp),
  /// recorded in every checkpoint.
  SolverSettings fingerprint;
  bool checkpoint_at_zone_exit = false;

  bool shaken() const { return source.fem.motion.has_value(); }
  /// The run starts from the geostatic state (its own, or a restart from fem_t0.000.h5)
  /// and switches to the failure models.
  bool switches_models() const { return !restart || record.stage == geostatic_stage; }
};

/// Resolves the plan of a run of `c` with `options` (reading the restart checkpoint);
/// Error (one line) on any bad input: options, the case's mesh and boundaries, a
/// checkpoint of another case, stage, element type or materials, or at the end time.
FemPlan plan_fem(const Case& c, const FemOptions& options, const Logger& log);

}  // namespace slide::fem
