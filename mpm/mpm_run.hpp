// A whole mpm-solve run: where the particles come from (particle file, restart, or the
// case geometry for pure MPM), the initial stresses of pure MPM, the time loop with its
// output cadence, the instability guard and the rest detection.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>

#include "common/base/log.hpp"
#include "common/base/ranks.hpp"
#include "common/input/case_file.hpp"

namespace slide::mpm {

struct RunOptions {
  std::filesystem::path output_dir;
  std::optional<std::filesystem::path> particles_file;  ///< --particles
  std::optional<std::filesystem::path> restart_file;    ///< --restart
  std::optional<double> until;                          ///< --until: stop earlier than the case
  bool write_vtk = true;
  /// --other-case: a particle file or checkpoint of another case is used (with a
  /// warning) instead of refused.
  bool other_case = false;
  /// --vtk-every: VTK frames every this many seconds (0: at every output step, as the
  /// history); none: the case's mpm.vtk_every, else run::automatic_vtk_every.
  std::optional<double> vtk_every;
  std::optional<ShapeFunction> shape_function;  ///< overrides the case
  std::optional<UpdateScheme> update_scheme;    ///< overrides the case
  std::optional<int> sort_interval;             ///< overrides the default (benchmarks)
  /// Read and check the case and the particles (file, restart or case geometry), then
  /// return before the initial stresses and the first file (the fuzz drivers, tests/fuzz/).
  bool inputs_only = false;
};

struct RunSummary {
  std::int64_t steps = 0;  ///< steps taken by this run (not counting a restart's earlier ones)
  std::size_t particles = 0;
  double wall_seconds = 0.0;
  double particle_steps_per_second = 0.0;
  double end_time = 0.0;
};

/// Runs the MPM phase of `c`; throws Error (one line) on bad input or an instability.
/// On several ranks (collective; docs/parallel.md) each rank reads its part of the
/// particle rows and keeps its slab's particles; the files are written together, the log
/// by the root.
RunSummary run_mpm(const Case& c, const RunOptions& options, const Logger& log,
                   const Ranks& ranks = Ranks::world());

}  // namespace slide::mpm
