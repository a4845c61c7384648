#include "mpm/mpm_run.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include <omp.h>

#include "common/base/error.hpp"
#include "common/input/motion.hpp"
#include "common/io/checkpoint.hpp"
#include "common/run/restart_record.hpp"
#include "common/run/stage.hpp"
#include "mpm/mpm_stage.hpp"

namespace slide::mpm {

namespace fs = std::filesystem;

namespace {

/// What messages call the particles' source.
std::string source_of(const MpmPlan& plan) {
  return plan.run.start_file.empty() ? plan.source.file.string() : plan.run.start_file.string();
}

void log_settings(const Logger& log, const MpmSettings& settings, const MpmSpec& spec, double dt) {
  const GridGeometry& grid = settings.grid;
  const std::string transfer =
      settings.velocity_transfer == VelocityTransfer::apic
          ? std::string(settings.pic_fraction > 0.0 ? "APIC (pic_fraction ignored)" : "APIC")
          : fmt::format("FLIP with PIC share {}", settings.pic_fraction);
  const std::string smoothing =
      settings.volumetric_smoothing == VolumetricSmoothing::none
          ? std::string("no volumetric smoothing")
          : fmt::format("volumetric smoothing {}", to_string(settings.volumetric_smoothing));
  log.info("grid {} × {} cells of {} m, {} shape functions, {}, {}, {}, Δt = {:.4g} s{}",
           grid.cells_x, grid.cells_y, grid.cell_size, to_string(settings.shape_function),
           to_string(settings.update_scheme), transfer, smoothing, dt,
           spec.time_step > 0.0 ? " (case)" : fmt::format(" (Courant C = {})", spec.courant));
  if (settings.shape_function == ShapeFunction::linear &&
      settings.velocity_transfer == VelocityTransfer::apic) {
    log.warning(
        "linear shape functions with APIC: particles running out alone drive nodes that carry "
        "a sliver of their mass, and APIC's affine velocity takes those nodes' velocities "
        "unweighted; column-short blows up within 1 s this way (mpm/README.md, \"Velocity "
        "transfer\"); gimp, or flip-pic, does not");
  }
}

/// The base motion the run continues (docs/method.md §8): the one its file records, or for
/// pure MPM of a shaken case the case's own, sampled at the first step (the grid's base
/// is rigid; an FE compliant base's motion is taken as grid_base_motion does).
void set_base_motion(const MpmPlan& plan, Start& start, MpmSolver& solver, const Logger& log) {
  const std::optional<MotionSpec>& spec = plan.source.motion;
  if (plan.run.start == run::Start::case_geometry && spec) {
    start.motion = checkpoint_motion(
        make_ground_motion(*spec, time_step(plan.source.mpm, solver), plan.run.end_time()),
        std::string(to_string(spec->base)), std::string(to_string(spec->input)));
  }
  if (!start.motion) return;
  solver.set_base_motion(grid_motion(*start.motion), *start.motion);
  const GroundMotion& m = *solver.base_motion();
  const auto peaks = m.peaks();
  log.info(
      "base motion from {} ({} base in FE{}): t = {:.3f} → {:.3f} s, peak |a| = {:.4g} m/s², "
      "|v| = {:.4g} m/s (x); the grid's edges move with it",
      source_of(plan), start.motion->base,
      start.motion->base == "compliant" ? fmt::format(", {} input", start.motion->input) : "",
      m.start_time(), m.end_time(), peaks.acceleration.x(), peaks.velocity.x());
  if (m.cut() && plan.run.end_time() > m.end_time()) {
    log.warning(
        "the motion's samples stop at t = {:.4g} s, the end of the case's runs when {} was "
        "written, but the record runs to {:.4g} s and this run to {:.4g} s: the base rests "
        "after {:.4g} s (rerun fem-solve with the later mpm.end_time to shake on)",
        m.end_time(), source_of(plan), m.record_end_time(), plan.run.end_time(), m.end_time());
  }
}

/// Refuses a run whose step is so small that it would never end (pure MPM's gravity
/// stage included), naming what made the step small.
void check_run_length(const MpmPlan& plan, const MpmSolver& solver, double dt) {
  const MpmSpec& spec = plan.source.mpm;
  const double gravity_stage =
      plan.run.start == run::Start::case_geometry && spec.initial_stress != InitialStress::k0
          ? spec.gravity_stage_duration
          : 0.0;
  run::check_step_count(
      gravity_stage + plan.run.end_time() - solver.clock().time, dt,
      spec.time_step > 0.0
          ? std::string("mpm.time_step is too small")
          : fmt::format("the Courant step C h / c is that small because a particle's p-wave "
                        "speed c = sqrt(M V / m) is {:.3g} m/s",
                        spec.courant * plan.settings.grid.cell_size / dt));
}

/// The slabs of a run on several ranks: cell columns and particles of each.
void log_slabs(const Logger& log, const Subdomain& domain, const MpmSolver& solver) {
  const Ranks& ranks = domain.ranks();
  std::vector<std::int64_t> counts(static_cast<std::size_t>(ranks.size()), 0);
  counts[static_cast<std::size_t>(ranks.rank())] = static_cast<std::int64_t>(solver.active_count());
  ranks.sum(std::span<std::int64_t>(counts));
  std::string slabs;
  for (int r = 0; r < ranks.size(); ++r) {
    const auto k = static_cast<std::size_t>(r);
    slabs += fmt::format("{}rank {}: cells {}–{}, {} particles", r == 0 ? "" : "; ", r,
                         domain.cuts().begin[k], domain.cuts().begin[k + 1] - 1, counts[k]);
  }
  log.info(
      "MPI: {} ranks of {} OpenMP thread(s), the grid cut into slabs of cell columns ({}); re-cut "
      "when a rank has {:.0f} % more particles than the mean",
      ranks.size(), omp_get_max_threads(), slabs, 100.0 * domain.rebalance_share);
}

/// What the ranks exchanged over the run (the scaling benchmark reads this line).
void log_exchanges(const Logger& log, const Subdomain& domain, std::int64_t steps) {
  const Ranks& ranks = domain.ranks();
  const double sent = ranks.sum(static_cast<double>(domain.bytes_sent));
  log.info(
      "MPI: {} re-cuts; {:.3g} MB sent between ranks in {} steps ({:.3g} kB per step per "
      "rank)",
      domain.recuts, sent / 1e6, steps,
      steps > 0 ? sent / 1e3 / static_cast<double>(steps) / ranks.size() : 0.0);
}

void log_memory(const Logger& log, const MpmSolver& solver) {
  const auto memory = solver.memory();
  const auto per_particle = [&](std::size_t bytes) {
    return static_cast<double>(bytes) /
           static_cast<double>(std::max<std::size_t>(solver.particles().count(), 1));
  };
  log.info(
      "memory: {:.0f} B/particle in particle arrays + {:.0f} B/particle sort peak + grid and "
      "windows {:.2f} MB ({:.0f} B/particle) = {:.0f} B/particle",
      per_particle(memory.particle_arrays), per_particle(memory.sort_peak),
      static_cast<double>(memory.grid) / 1e6, per_particle(memory.grid),
      per_particle(memory.total()));
}

/// How far the body's front (the largest x + l_x/2 of its particles above the case's
/// foundation level, frozen ones included: a particle that left through the far edge is
/// frozen there) is from the grid's far edge in +x, the runout direction, m. A foundation
/// layer across the grid is not the slide (docs/method.md §6, measured particles).
double far_edge_clearance(const MpmSolver& solver, double foundation_level, const Ranks& ranks) {
  const Particles& p = solver.particles();
  double front = -std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < p.count(); ++k) {
    if (p.coordinates[k].y() > foundation_level)
      front = std::max(front, p.coordinates[k].x() + 0.5 * p.size[k].x());
  }
  return solver.settings().grid.upper_corner().x() - ranks.max(front);
}

/// Warns when a body that started more than a cell from the grid's far edge ends within
/// one: its runout is then the grid's, not the slide's (slope-frictional's front piled
/// against its 150 m wall and its R_N was the grid's length). A body that starts there
/// is not warned of: its front is not a runout.
void check_far_edge(const Logger& log, const MpmSolver& solver, double foundation_level,
                    double clearance_at_start, const Ranks& ranks) {
  const double cell = solver.settings().grid.cell_size;
  const double clearance = far_edge_clearance(solver, foundation_level, ranks);
  if (clearance_at_start < cell || clearance >= cell) return;
  log.warning(
      "the body ends against the grid's far edge (x = {:g} m, its front {:.2f} m from it, less "
      "than a cell): its runout is the grid's; extend [mpm] domain in +x",
      solver.settings().grid.upper_corner().x(), std::max(clearance, 0.0));
}

/// The particles on the plan's grid (one line naming the first bad one), the solver
/// taking them, the base motion, the ranks' slabs, and what a restart's run changed.
void set_up(const MpmPlan& plan, Start& start, std::optional<MpmSolver>& solver, const Logger& log,
            const Ranks& ranks) {
  // A shaken run's grid is where the base is at the start (MpmSolver::set_base_motion).
  MpmSettings placed = plan.settings;
  if (start.motion) {
    placed.grid.origin +=
        base_position(*start.motion, grid_motion(*start.motion), start.clock.time);
  }
  agreed(ranks, [&] {
    validate_particles(start.particles, placed, plan.source.materials.size(), source_of(plan),
                       start.clock.frozen);
    return 0;
  });
  solver.emplace(plan.settings, plan.source.materials, std::move(start.particles), start.clock);
  set_base_motion(plan, start, *solver, log);
  // On several ranks, each keeps its slab's share of the particles from here on; a
  // restart on as many ranks as its checkpoint's takes that checkpoint's slabs, and each
  // rank the particles it held.
  std::optional<Decomposition> restarted;
  if (plan.record && ranks.distributed()) {
    restarted = restart_slabs(*plan.record, start.file_rows, start.first_row, ranks.size(),
                              plan.run.start_file.string());
  }
  solver->distribute(ranks, restarted.value_or(Decomposition{}));
  if (const Subdomain* domain = solver->subdomain()) {
    // Each part's ids were checked among themselves as they were read; now across parts.
    if (const auto duplicate = duplicate_id(solver->particles(), ranks)) {
      throw Error("{}: particles on ranks share id {}, expected unique ids", source_of(plan),
                  *duplicate);
    }
    log_slabs(log, *domain, *solver);
  }
  const MpmSpec& spec = plan.source.mpm;
  start.references.time_step = spec.time_step;
  start.references.courant = spec.courant;
}

}  // namespace

RunSummary run_mpm(const MpmPlan& plan, const Logger& log, const Ranks& ranks) {
  Start start = agreed(ranks, [&] { return load_start(plan, log, ranks); });
  std::optional<MpmSolver> solver;
  set_up(plan, start, solver, log, ranks);
  // The first step, for the log and the run's length; the stage takes each anew.
  const double dt = time_step(plan.source.mpm, *solver);
  log_settings(log, plan.settings, plan.source.mpm, dt);
  check_run_length(plan, *solver, dt);
  if (plan.run.inputs_only) return {};

  const double foundation_level = plan.source.metrics.foundation_level;
  const double clearance_at_start = far_edge_clearance(*solver, foundation_level, ranks);
  MpmStage stage(plan, *solver, start, log);
  const run::RunResult result = run::execute(stage, plan.run, log, ranks);
  if (const Subdomain* domain = solver->subdomain()) {
    log_exchanges(log, *domain, result.work.steps);
  }
  log_memory(log, *solver);
  check_far_edge(log, *solver, foundation_level, clearance_at_start, ranks);
  return {result.work.steps, static_cast<std::size_t>(result.work.units), result.wall_seconds,
          result.wall_seconds > 0.0 ? result.work.unit_steps / result.wall_seconds : 0.0,
          solver->clock().time};
}

}  // namespace slide::mpm
