#include "mpm/mpm_plan.hpp"

#include <cmath>

#include "common/base/error.hpp"
#include "common/input/case_file.hpp"
#include "common/input/mesh_generation.hpp"
#include "common/io/checkpoint.hpp"
#include "common/run/stage.hpp"

namespace slide::mpm {

namespace {

/// The case's MPM settings with the command line's overrides.
MpmSettings settings_for(const Case& c, const RunOptions& options) {
  MpmSettings settings = MpmSettings::from(c.mpm);
  settings.gravity = c.gravity;
  if (options.shape_function) settings.shape_function = *options.shape_function;
  if (options.update_scheme) settings.update_scheme = *options.update_scheme;
  if (options.sort_interval) settings.sort_interval = *options.sort_interval;
  return settings;
}

MpmCase case_of(const Case& c, bool pure_mpm) {
  MpmCase source{c.name, c.file, c.materials, c.mpm, c.metrics, std::nullopt, std::nullopt};
  if (pure_mpm) {
    source.body = build_mesh(c);
    source.motion = c.fem.motion;
  }
  return source;
}

/// The file's header: of this case (or --other-case), and of an mpm run for a restart.
CheckpointHeader checked_header(const Case& c, const RunOptions& options,
                                const std::filesystem::path& path) {
  const CheckpointHeader header = read_checkpoint_header(path);
  if (header.case_name != c.name && !options.other_case) {
    throw Error(
        "{}: written for case \"{}\", not for case \"{}\" of {} (--other-case to use it anyway)",
        path.string(), header.case_name, c.name, c.file.string());
  }
  if (options.restart_file && header.kind != CheckpointKind::mpm) {
    throw Error("{}: is a {} file; --restart takes an mpm-solve checkpoint (kind mpm)",
                path.string(), to_string(header.kind));
  }
  return header;
}

/// Refuses an end before the start, and a restart at its end: it has nothing to continue
/// (fem-solve refuses the same); a fresh run may end where it starts (--until 0: the
/// start checkpoint only).
void check_end(const MpmPlan& plan, double start_time, bool until) {
  const double end = plan.run.end_time();
  const std::string source =
      plan.run.start_file.empty() ? plan.source.file.string() : plan.run.start_file.string();
  if (end < start_time) {
    throw Error("{}: the run would end at t = {} s, before its start at t = {} s{}", source, end,
                start_time, until ? " (--until)" : " (mpm.end_time)");
  }
  if (plan.run.start == run::Start::restart &&
      !(end > start_time + run::OutputSchedule::tolerance(end))) {
    throw Error(
        "{}: the checkpoint time {:.3f} s is at or after the end time {:.3f} s{}: nothing to "
        "continue",
        source, start_time, end, until ? " (--until)" : "");
  }
}

}  // namespace

MpmPlan plan_mpm(const Case& c, const RunOptions& options) {
  if (options.until && !std::isfinite(*options.until)) {
    throw Error("--until {} is not admissible (expected a finite end time in s)", *options.until);
  }
  if (options.particles_file && options.restart_file) {
    throw Error("--particles and --restart exclude each other (a restart carries its particles)");
  }
  MpmPlan plan;
  run::Plan& run = plan.run;
  run.case_name = c.name;
  run.start = options.restart_file     ? run::Start::restart
              : options.particles_file ? run::Start::particle_file
                                       : run::Start::case_geometry;
  run.start_file = options.restart_file.value_or(options.particles_file.value_or(""));
  plan.source = case_of(c, run.start == run::Start::case_geometry);
  plan.settings = settings_for(c, options);
  plan.other_case = options.other_case;
  // Where the stage starts: its clock, and the stage's own start (the transfer time, or
  // 0 for pure MPM) from which the automatic VTK cadence counts, so that a restart writes
  // the frames the uninterrupted run writes.
  double start_time = 0.0, stage_start = 0.0;
  if (!run.start_file.empty()) {
    start_time = checked_header(c, options, run.start_file).time;
    stage_start = run.start == run::Start::restart
                      ? read_checkpoint_transfer(run.start_file).transfer_time
                      : start_time;
  }
  const double end = std::min(c.mpm.end_time, options.until.value_or(c.mpm.end_time));
  run.schedule = run::OutputSchedule(end, c.mpm.output_every, {c.mpm.checkpoint_every},
                                     c.mpm.checkpoint_times);
  check_end(plan, start_time, options.until.has_value());
  // Every checkpoint under a name of its own (a fresh run checkpoints its start).
  run::check_checkpoint_cadence(c.mpm.checkpoint_every, "mpm.checkpoint_every");
  run::check_checkpoint_times(c.mpm.checkpoint_times, "mpm", "mpm.checkpoint_times",
                              {start_time});
  run.output = {options.output_dir, "mpm", options.write_vtk,
                run::choose_vtk_every(options.vtk_every, c.mpm.vtk_every, stage_start, end,
                                      c.mpm.output_every),
                false, true};
  run.resume_outputs = run.start == run::Start::restart;
  run.inputs_only = options.inputs_only;
  return plan;
}

}  // namespace slide::mpm
