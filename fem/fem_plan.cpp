#include "fem/fem_plan.hpp"

#include <array>

#include "common/base/error.hpp"
#include "common/input/case_file.hpp"
#include "common/input/case_fingerprint.hpp"
#include "common/input/mesh_generation.hpp"
#include "common/run/stage.hpp"
#include "fem/fem_model.hpp"

namespace slide::fem {

namespace {

/// The restart record's entries, each checked on reading.
constexpr std::array<run::RecordEntry<FemRecord>, 9> record_table{{
    {"stage", &FemRecord::stage},
    {"kinematics", &FemRecord::kinematics, -run::unbounded, run::unbounded, run::Need::optional},
    {"element_type", &FemRecord::element_type, -run::unbounded, run::unbounded,
     run::Need::optional},
    {"courant", &FemRecord::courant, 0.0, run::unbounded, run::Need::optional},
    {"time_step", &FemRecord::time_step, 0.0, run::unbounded, run::Need::optional},
    {"hourglass_coefficient", &FemRecord::hourglass_coefficient, 0.0, run::unbounded,
     run::Need::optional},
    // The failure stage's energy reference ("initial_total_energy" before the shared run
    // loop); none in the geostatic checkpoint.
    {"initial_energy", &FemRecord::initial_energy, -run::unbounded, run::unbounded,
     run::Need::optional, "initial_total_energy"},
    {"energy_scale", &FemRecord::energy_scale, 0.0, run::unbounded, run::Need::optional},
    // Shaken failure stages only.
    {"boundary_work", &FemRecord::boundary_work, -run::unbounded, run::unbounded,
     run::Need::optional},
}};

/// The case with the command line's overrides.
Case with_overrides(Case c, const FemOptions& options) {
  if (options.element) c.mesh.element_type = *options.element;
  if (options.kinematics) c.fem.kinematics = *options.kinematics;
  return c;
}

void check_options(const Case& c, const FemOptions& options, double end) {
  if (c.fem.failure_stage && !(end > 0.0)) {
    throw Error("--until {} is not admissible (expected an end time > 0 s)", end);
  }
  if (options.checkpoint_every < 0.0) {
    throw Error("--checkpoint-every {} is not admissible (expected ≥ 0 s)",
                options.checkpoint_every);
  }
  // Every checkpoint under a name of its own (fem_t0.000.h5 is the geostatic state).
  run::check_checkpoint_cadence(options.checkpoint_every, "--checkpoint-every");
  run::check_checkpoint_cadence(c.fem.checkpoint_every, "fem.checkpoint_every");
  run::check_checkpoint_times(c.fem.checkpoint_times, "fem", "fem.checkpoint_times", {0.0});
}

/// The checkpoint a restart continues, checked against the case; its mesh goes to the plan.
void plan_restart(const Case& c, const FemOptions& options, FemPlan& plan, const Logger& log) {
  const std::filesystem::path& file = *options.restart;
  const CheckpointHeader header = read_checkpoint_header(file);
  if (header.kind != CheckpointKind::fem) {
    throw Error("{}: checkpoint kind is \"{}\", fem-solve restarts from a kind \"fem\" checkpoint",
                file.string(), to_string(header.kind));
  }
  FemCheckpoint checkpoint = read_fem_checkpoint(file);
  if (checkpoint.header.case_name != c.name) {
    throw Error("{}: written for case \"{}\", not for case \"{}\" of {}", file.string(),
                checkpoint.header.case_name, c.name, c.file.string());
  }
  if (checkpoint.mesh.element_type != c.mesh.element_type) {
    throw Error("{}: the checkpoint has {} elements but the case asks for {}", file.string(),
                to_string(checkpoint.mesh.element_type), to_string(c.mesh.element_type));
  }
  run::check_restart_materials(checkpoint.materials, c.materials, file.string());
  plan.record = read_record(checkpoint.solver, file.string());
  check_unchanged(checkpoint.solver, plan.fingerprint, options.allow_changed, file.string(), log);
  if (!c.fem.failure_stage) {
    throw Error(
        "{}: the case has no failure stage (fem.failure_stage = false), nothing to "
        "continue",
        file.string());
  }
  const run::OutputSchedule& schedule = plan.run.schedule;
  if (!(checkpoint.header.time < schedule.end_time()) || schedule.is_end(checkpoint.header.time)) {
    throw Error("{}: the checkpoint time {:.3f} s is at or after the end time {:.3f} s",
                file.string(), checkpoint.header.time, schedule.end_time());
  }
  validate_mesh(checkpoint.mesh, file.string(), c.materials.size());
  make_constraints(checkpoint.mesh, c.fem.failure_boundaries, "fem.failure.boundaries");
  plan.mesh = std::move(checkpoint.mesh);
  plan.restart = std::move(checkpoint);
}

}  // namespace

SolverSettings write_record(const FemRecord& record) {
  return run::write_record(record, record_table);
}

FemRecord read_record(const SolverSettings& settings, const std::string& source) {
  FemRecord record = run::read_record(settings, record_table, source, FemRecord{});
  if (record.stage != geostatic_stage && record.stage != failure_stage) {
    throw Error("{}: /solver attribute stage is \"{}\" (expected \"geostatic\" or \"failure\")",
                source, record.stage);
  }
  return record;
}

FemPlan plan_fem(const Case& original, const FemOptions& options, const Logger& log) {
  const Case c = with_overrides(original, options);
  const double end = options.until.value_or(c.fem.end_time);
  check_options(c, options, end);
  FemPlan plan;
  plan.source = {c.name, c.file, c.materials, c.gravity, c.fem, std::max(end, c.mpm.end_time)};
  plan.checkpoint_at_zone_exit = options.checkpoint_at_zone_exit;
  plan.fingerprint = fem_fingerprint(c);
  run::Plan& run = plan.run;
  run.case_name = c.name;
  run.inputs.push_back(c.file);
  if (!c.mesh.file().empty()) run.inputs.push_back(c.mesh.file());
  run.schedule = run::OutputSchedule(end, c.fem.output_every,
                                     {c.fem.checkpoint_every, options.checkpoint_every},
                                     c.fem.checkpoint_times);
  run.output = {
      options.output_dir,
      "fem",
      options.write_vtk,
      run::choose_vtk_every(options.vtk_every, c.fem.vtk_every, 0.0, end, c.fem.output_every),
      c.fem.failure_stage,
      false};
  run.inputs_only = options.inputs_only;
  run.disk_check = options.disk_check;
  if (options.restart) {
    run.start = run::Start::restart;
    run.start_file = *options.restart;
    plan_restart(c, options, plan, log);
    // From the geostatic state (fem_t0.000.h5, written before the t = 0 outputs) the
    // failure stage starts afresh: its outputs too, so that t = 0 rows and frames a
    // killed run left incomplete are written again.
    run.resume_outputs = plan.record.stage != geostatic_stage;
    return plan;
  }
  // Everything that can reject the input happens before the first file is written.
  plan.mesh = build_mesh(c);
  make_constraints(plan.mesh, c.fem.geostatic_boundaries, "fem.geostatic.boundaries");
  if (c.fem.failure_stage) {
    make_constraints(plan.mesh, c.fem.failure_boundaries, "fem.failure.boundaries");
  }
  return plan;
}

}  // namespace slide::fem
