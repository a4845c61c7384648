#include "mpm/mpm_plan.hpp"

#include <cmath>

#include "common/base/error.hpp"
#include "common/input/case_file.hpp"
#include "common/input/case_fingerprint.hpp"
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

/// The file a run starts from, but its particle rows: of this case (or --other-case),
/// and for a restart an mpm checkpoint with a sound record.
ParticleCheckpoint checked_start_file(const Case& c, const RunOptions& options,
                                      const std::filesystem::path& path) {
  ParticleCheckpoint file = read_particle_checkpoint_settings(path);
  if (file.header.case_name != c.name && !options.other_case) {
    throw Error(
        "{}: written for case \"{}\", not for case \"{}\" of {} (--other-case to use it anyway)",
        path.string(), file.header.case_name, c.name, c.file.string());
  }
  return file;
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

MpmPlan plan_mpm(const Case& c, const RunOptions& options, const Logger& log) {
  if (options.until && !std::isfinite(*options.until)) {
    throw Error("--until {} is not admissible (expected a finite end time in s)", *options.until);
  }
  if (options.particles_file && options.restart) {
    throw Error("--particles and --restart exclude each other (a restart carries its particles)");
  }
  MpmPlan plan;
  run::Plan& run = plan.run;
  run.case_name = c.name;
  run.inputs.push_back(c.file);
  if (!c.mesh.file().empty()) run.inputs.push_back(c.mesh.file());
  run.start = options.restart          ? run::Start::restart
              : options.particles_file ? run::Start::particle_file
                                       : run::Start::case_geometry;
  run.start_file = options.restart.value_or(options.particles_file.value_or(""));
  plan.source = case_of(c, run.start == run::Start::case_geometry);
  plan.settings = settings_for(c, options);
  plan.other_case = options.other_case;
  plan.fingerprint = mpm_fingerprint(c, run.start == run::Start::case_geometry);
  // Where the stage starts: its clock, and the stage's own start (the transfer time, or
  // 0 for pure MPM) from which the automatic VTK cadence counts, so that a restart writes
  // the frames the uninterrupted run writes.
  double start_time = 0.0, stage_start = 0.0;
  if (!run.start_file.empty()) {
    const ParticleCheckpoint file = checked_start_file(c, options, run.start_file);
    start_time = stage_start = file.header.time;
    if (run.start == run::Start::restart) {
      plan.record = read_mpm_record(file, run.start_file.string());
      // A restart of pure MPM keeps recording the geometry and start it came from.
      plan.fingerprint = mpm_fingerprint(c, file.solver.contains("case_start"));
      check_unchanged(file.solver, plan.fingerprint, options.allow_changed, run.start_file.string(),
                      log);
      stage_start = file.transfer.transfer_time;
    }
  }
  const double end = std::min(c.mpm.end_time, options.until.value_or(c.mpm.end_time));
  run.schedule = run::OutputSchedule(end, c.mpm.output_every, {c.mpm.checkpoint_every},
                                     c.mpm.checkpoint_times);
  check_end(plan, start_time, options.until.has_value());
  // Every checkpoint under a name of its own (a fresh run checkpoints its start).
  run::check_checkpoint_cadence(c.mpm.checkpoint_every, "mpm.checkpoint_every");
  run::check_checkpoint_times(c.mpm.checkpoint_times, "mpm", "mpm.checkpoint_times", {start_time});
  run.output = {options.output_dir,
                "mpm",
                options.write_vtk,
                run::choose_vtk_every(options.vtk_every, c.mpm.vtk_every, stage_start, end,
                                      c.mpm.output_every),
                false,
                true};
  run.resume_outputs = run.start == run::Start::restart;
  run.inputs_only = options.inputs_only;
  run.disk_check = options.disk_check;
  return plan;
}

}  // namespace slide::mpm
