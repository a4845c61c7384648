// A whole mpm-solve run: the plan (mpm_plan.hpp) carried out: the particles it starts
// from, the solver, the stage (mpm_stage.hpp) and the shared run lifecycle
// (run::execute: outputs, the guard, the loop, the final files and the summary line).
#pragma once

#include <cstdint>

#include "common/base/log.hpp"
#include "common/base/ranks.hpp"
#include "mpm/mpm_plan.hpp"

namespace slide::mpm {

struct RunSummary {
  std::int64_t steps = 0;  ///< steps taken by this run (not counting a restart's earlier ones)
  std::size_t particles = 0;
  double wall_seconds = 0.0;
  double particle_steps_per_second = 0.0;
  double end_time = 0.0;
};

/// Runs the MPM phase as `plan` says; throws Error (one line) on bad input or an
/// instability. On several ranks (collective; docs/parallel.md) each rank reads its part
/// of the particle rows and keeps its slab's particles; the files are written together,
/// the log by the root.
RunSummary run_mpm(const MpmPlan& plan, const Logger& log, const Ranks& ranks = Ranks::world());

}  // namespace slide::mpm
