#include "mpm/mpm_run.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <type_traits>

#include <omp.h>

#include "common/base/error.hpp"
#include "common/input/mesh_generation.hpp"
#include "common/input/motion.hpp"
#include "common/io/checkpoint.hpp"
#include "common/run/output_schedule.hpp"
#include "common/run/stability_guard.hpp"
#include "common/run/stage.hpp"
#include "mpm/mpm_output.hpp"
#include "mpm/mpm_solver.hpp"
#include "mpm/particle_generation.hpp"

namespace slide::mpm {

namespace fs = std::filesystem;

namespace {

/// Where the run starts from.
struct Start {
  Particles particles;
  SolverClock clock;
  RunReferences references;
  TransferSettings transfer;
  std::optional<SolverSettings> stored_settings;  ///< restart: the settings it ran with
  bool fresh = true;      ///< not a restart: t0 outputs and references still to set
  bool pure_mpm = false;  ///< particles from the case geometry
  Mesh body;              ///< pure MPM: the body's mesh (surface heights for K0)
  std::optional<CheckpointMotion> motion;  ///< the base motion the file carries
};

// A particle file's materials must be the case's by count, name and density (its
// particle masses were computed with that density); their other properties may differ:
// rerunning the runout of one transfer with other strengths is a study users make, so
// the case file's values are used and the change is logged.
void compare_materials(const MaterialTable& from_file, const MaterialTable& from_case,
                       const std::string& source, const Logger& log) {
  run::check_restart_materials(from_file, from_case, source);
  for (std::size_t m = 0; m < from_file.size(); ++m) {
    const Material& a = from_file[m];
    const Material& b = from_case[m];
    if (a.model != b.model || a.mpm_model != b.mpm_model || a.youngs_modulus != b.youngs_modulus ||
        a.poisson_ratio != b.poisson_ratio || a.friction_angle != b.friction_angle ||
        a.cohesion != b.cohesion || a.dilation_angle != b.dilation_angle ||
        a.tension_cutoff != b.tension_cutoff) {
      log.warning("{}: material \"{}\" differs from the case file's; the case file's is used",
                  source, b.name);
    }
  }
}

Start start_from_file(const Case& c, const RunOptions& options, const Logger& log,
                      const Ranks& ranks) {
  Start start;
  const bool restart = options.restart_file.has_value();
  const fs::path path = restart ? *options.restart_file : *options.particles_file;
  // On several ranks each reads its part of the rows (MpmSolver::distribute).
  ParticleCheckpoint file = read_particle_checkpoint(path, ranks.part());
  if (file.header.case_name != c.name) {
    if (!options.other_case) {
      throw Error(
          "{}: written for case \"{}\", not for case \"{}\" of {} (--other-case to use it "
          "anyway)",
          path.string(), file.header.case_name, c.name, c.file.string());
    }
    log.warning("{}: written for case \"{}\", run with case \"{}\" (--other-case)", path.string(),
                file.header.case_name, c.name);
  }
  if (restart) {
    run::check_restart_materials(file.materials, c.materials, path.string());
  } else {
    compare_materials(file.materials, c.materials, path.string(), log);
  }
  start.transfer = file.transfer;
  start.motion = file.motion;
  if (restart) {
    read_restart_state(file, path.string(), start.clock, start.references);
    start.stored_settings = file.solver;
    start.fresh = false;
    log.info("restart from {} at t = {} s (step {})", path.string(), start.clock.time,
             start.clock.step);
  } else {
    start.clock.time = file.header.time;
    start.references.pe0 = file.header.pe0;
    log.info("{} particles from {} ({} file) at t = {} s", file.file_rows, path.string(),
             to_string(file.header.kind), file.header.time);
  }
  // The file's frozen rows are its last ones: those of this part stay last in it.
  if (start.clock.frozen > file.file_rows) {
    throw Error("{}: {} frozen particles of {}", path.string(), start.clock.frozen, file.file_rows);
  }
  const RowSpan rows{file.first_row, file.first_row + file.particles.count()};
  start.clock.frozen = rows.last_rows_within(file.file_rows, start.clock.frozen);
  start.particles = std::move(file.particles);
  return start;
}

/// Pure MPM's particles from the case geometry, with the K0 stresses of level ground when
/// the case asks for them (the gravity stage needs the solver: initialise_pure_mpm).
Start start_pure_mpm(const Case& c, const MpmSettings& settings, const Logger& log,
                     const Ranks& ranks) {
  Start start;
  start.pure_mpm = true;
  start.body = build_mesh(c);
  Particles& p = start.particles;
  // On several ranks each makes its part of the body's rows (MpmSolver::distribute).
  std::size_t body_count = 0;
  p = generate_mesh_particles(settings.grid, start.body, c.mpm.particles_x, c.mpm.particles_y,
                              c.materials, ranks.part(), &body_count);
  log.info("pure MPM: {} particles ({} × {} per cell) in the {} elements of the case geometry",
           body_count, c.mpm.particles_x, c.mpm.particles_y, start.body.element_count());
  if (c.mpm.initial_stress == InitialStress::k0) {
    apply_k0_stresses(p, c.materials, mesh_surface_heights(start.body, p.coordinates),
                      -settings.gravity.y());
    log.info("pure MPM: K0 stresses of level ground (K0 = ν/(1 − ν))");
  }
  return start;
}

/// f() on every rank, as one decision (collective): when it throws Error on some ranks
/// (a bad row in one rank's part of a particle file), every rank throws the message of
/// the lowest of them, so that the run ends with its one line instead of an abort.
template <class F>
std::invoke_result_t<F> agreed(const Ranks& ranks, F&& f) {
  std::invoke_result_t<F> result{};
  std::optional<std::string> problem;
  try {
    result = f();
  } catch (const Error& e) {
    problem = e.what();
  }
  if (const auto first = ranks.first_problem(problem)) throw Error("{}", *first);
  return result;
}

/// Particles on every rank together (collective).
std::size_t total_particles(const MpmSolver& solver) {
  return static_cast<std::size_t>(
      solver.ranks().sum(static_cast<double>(solver.particles().count())));
}

/// MpmSolver::return_to_yield_surface on every rank: how many particles it returned in all
/// (collective).
std::size_t return_to_yield_surface(MpmSolver& solver) {
  return static_cast<std::size_t>(
      solver.ranks().sum(static_cast<double>(solver.return_to_yield_surface())));
}

/// The initial stresses of pure MPM (docs/method.md §5): K0 of level ground (set on the
/// particles already), or an elastic gravity stage with damping to equilibrium; then the
/// switch to the plastic model.
void initialise_pure_mpm(const Case& c, MpmSolver& solver, double dt, const Logger& log) {
  if (c.mpm.initial_stress != InitialStress::k0) {
    // Elastic loading under gravity with local damping, then the state reset: the
    // equilibrium state of t = 0.
    const auto settling =
        solver.settle_under_gravity(c.mpm.gravity_stage_duration, c.mpm.gravity_stage_damping, dt);
    log.info(
        "pure MPM: elastic gravity stage, {} s in {} steps (damping α = {}), KE {:.4g} J/m at its "
        "end",
        c.mpm.gravity_stage_duration, settling.steps, c.mpm.gravity_stage_damping,
        settling.kinetic_energy);
  }
  const std::size_t returned = return_to_yield_surface(solver);
  log.info(
      "pure MPM: switch to the plastic model: {} of {} particles returned to the yield surface",
      returned, total_particles(solver));
}

/// Fixes the guard's references at the start of a fresh run (collective).
void set_references(const Case& c, const MpmSolver& solver, RunReferences& r, bool pure_mpm,
                    const Logger& log) {
  const Particles& p = solver.particles();
  const Ranks& ranks = solver.ranks();
  const Energies e = solver.energies();
  const double g = solver.settings().gravity.norm();
  double y_min = std::numeric_limits<double>::infinity(), y_max = -y_min;
  for (const Vec2& x : p.coordinates) {
    y_min = std::min(y_min, x.y());
    y_max = std::max(y_max, x.y());
  }
  y_min = ranks.min(y_min);
  y_max = ranks.max(y_max);
  if (pure_mpm || !(r.pe0 != 0.0)) {
    if (!pure_mpm)
      log.warning("the particle file has pe0 = 0; PE0 = Σ m g y of its particles is used");
    r.pe0 = e.potential;
  }
  r.reference_height = c.metrics.initial_height > 0.0 ? c.metrics.initial_height : y_max - y_min;
  r.energy.initial_energy = e.total();
  double releasable = 0.0;
  for (std::size_t k = 0; k < p.count(); ++k)
    releasable += p.mass[k] * g * (p.coordinates[k].y() - y_min);
  releasable = ranks.sum(releasable);
  r.energy.energy_scale = releasable + e.kinetic + e.elastic;
  r.rest_timer = 0.0;
}

/// The guard's checks of this rank's particles and nodes: finite fields, speeds below
/// the bound (the energy is the whole body's: check_stability).
std::optional<std::string> check_own_stability(const MpmSolver& solver, const RunReferences& r,
                                               double speed_limit_factor) {
  const Particles& p = solver.particles();
  for (std::size_t k = 0; k < p.count(); ++k) {
    if (!p.velocity[k].allFinite() || !p.stress[k].allFinite() || !std::isfinite(p.volume[k])) {
      return fmt::format("particle {} (id {}) has a non-finite velocity, stress or volume", k,
                         p.id[k]);
    }
  }
  const double limit =
      run::speed_limit(speed_limit_factor, solver.settings().gravity.norm(), r.reference_height);
  const auto speeds = solver.max_speeds();
  if (limit > 0.0 && speeds.particle > limit) {
    const std::size_t k = speeds.particle_index;
    return fmt::format(
        "particle {} (id {}) at ({:.3f}, {:.3f}) m moves at {:.4g} m/s, above {} × "
        "sqrt(2 g H) = {:.4g} m/s (H = {} m)",
        k, p.id[k], p.coordinates[k].x(), p.coordinates[k].y(), speeds.particle, speed_limit_factor,
        limit, r.reference_height);
  }
  if (limit > 0.0 && speeds.node > limit) {
    return fmt::format(
        "grid node at ({:.3f}, {:.3f}) m moves at {:.4g} m/s, above {} × sqrt(2 g H) = "
        "{:.4g} m/s (H = {} m)",
        speeds.node_position.x(), speeds.node_position.y(), speeds.node, speed_limit_factor, limit,
        r.reference_height);
  }
  return std::nullopt;
}

/// The instability guard (docs/method.md §5; the checks and the tolerance are shared,
/// common/run/stability_guard.hpp): finite particle fields, particle and node speeds
/// below the bound, the total energy within the shared tolerance. Collective: every
/// rank checks its particles and nodes, and all take the first rank's finding.
std::optional<std::string> check_stability(const MpmSolver& solver, const RunReferences& r,
                                           double speed_limit_factor) {
  const auto local = check_own_stability(solver, r, speed_limit_factor);
  if (auto problem = solver.ranks().first_problem(local)) return problem;
  const Energies e = solver.energies();
  return run::energy_growth(
      e.total() - solver.clock().boundary_work, r.energy,
      fmt::format("kinetic {:.4g} + potential + elastic {:.4g} J/m", e.kinetic, e.elastic));
}

/// Warnings about particles leaving the grid, rate-limited: the first exit at once, then
/// one warning per checkpoint for the exits since the last warning (a body pouring over
/// the grid's edge loses particles on hundreds of steps), and the run's total at its end.
class ExitLog {
 public:
  ExitLog(const Logger& log, ParticleExit mode)
      : log_(log), fate_(mode == ParticleExit::freeze ? "were frozen" : "were removed") {}

  /// `count` particles left the grid in the step that ended at `time`.
  void add(std::size_t count, double time) {
    if (count == 0) return;
    total_ += count;
    if (total_ == count) {
      first_exit_ = time;
      log_.warning(
          "{} particle{} left the grid at t = {:.4f} s and {}; further exits are reported at "
          "the checkpoints",
          count, plural(count), time, fate_);
      return;
    }
    if (unreported_ == 0) first_unreported_ = time;
    unreported_ += count;
  }
  /// At a checkpoint: the exits since the last warning.
  void report(double time) {
    if (unreported_ == 0) return;
    log_.warning(
        "{} more particle{} left the grid between t = {:.4f} and {:.4f} s and {} ({} in all)",
        unreported_, plural(unreported_), first_unreported_, time, fate_, total_);
    unreported_ = 0;
  }
  /// At the end of the run: the last exits not reported yet, and the total.
  void finish(double time) {
    if (total_ == 0) return;
    report(time);
    log_.warning("{} particle{} left the grid in this run (the first at t = {:.4f} s) and {}",
                 total_, plural(total_), first_exit_, fate_);
  }

 private:
  static const char* plural(std::size_t n) { return n == 1 ? "" : "s"; }

  const Logger& log_;
  const char* fate_;
  std::size_t total_ = 0, unreported_ = 0;
  double first_exit_ = 0.0, first_unreported_ = 0.0;
};

/// The step: the case's, or the Courant step at the particles' current densities, taken
/// anew every step (mpm/README.md, "Time step").
double time_step(const MpmSpec& spec, const MpmSolver& solver) {
  return spec.time_step > 0.0 ? spec.time_step : solver.courant_time_step(spec.courant);
}

/// mpm-solve's time loop (run::Stage): steps of the case's Δt or of the Courant step at
/// the particles' current densities, landing on the schedule's times; the rest
/// detection; at each output the guard, the history row, the VTK frame, the checkpoint.
class MpmStage final : public run::Stage {
 public:
  MpmStage(const Case& c, const RunOptions& options, const run::OutputSchedule& schedule,
           MpmSolver& solver, RunReferences& references, const TransferSettings& transfer,
           const std::optional<CheckpointMotion>& motion, MpmHistory& history,
           std::optional<VtkWriter>& vtk, double vtk_every, Progress& progress, ExitLog& exits,
           fs::path last_checkpoint, const Logger& log)
      : case_(c),
        options_(options),
        schedule_(schedule),
        solver_(solver),
        refs_(references),
        transfer_(transfer),
        motion_(motion),
        history_(history),
        vtk_(vtk),
        vtk_every_(vtk_every),
        progress_(progress),
        exits_(exits),
        last_checkpoint_(std::move(last_checkpoint)),
        log_(log) {}

  double time() const override { return solver_.clock().time; }
  std::int64_t steps() const { return steps_; }
  /// The output of a fresh run's start (a VTK frame whatever the cadence).
  void write_start_output(bool checkpoint) { write_output_at(checkpoint, true); }
  /// The last output of the run (a VTK frame whatever the cadence).
  void write_last_output() { write_output_at(false, true); }
  double particle_steps() const { return particle_steps_; }

  bool advance_to(double stop) override {
    for (;;) {
      const double time = solver_.clock().time;
      const double step = time_step(case_.mpm, solver_);
      const bool landing = time + step >= stop;
      particle_steps_ += static_cast<double>(solver_.active_count());
      const StepReport report = solver_.step(landing ? stop - time : step);
      if (landing) solver_.land_on(stop);  // exactly, so restarts line up
      ++steps_;

      const double now = solver_.clock().time;
      exits_.add(report.exited, now);
      const double ke_over_pe0 = solver_.last_kinetic_energy() / refs_.pe0;
      refs_.rest_timer =
          ke_over_pe0 < case_.mpm.rest_threshold ? refs_.rest_timer + (now - time) : 0.0;
      const bool at_rest =
          case_.mpm.rest_duration > 0.0 && refs_.rest_timer >= case_.mpm.rest_duration;
      progress_.update(now, solver_.clock().step,
                       fmt::format("KE/PE0 {:.3g} Δt {:.3g} s", ke_over_pe0, step));
      if (at_rest) {
        log_.info("at rest: KE/PE0 < {} for {} s, stopping at t = {:.4f} s",
                  case_.mpm.rest_threshold, case_.mpm.rest_duration, now);
        return false;
      }
      // A step that ends within the schedule's tolerance of an output time is on it.
      if (landing || schedule_.is_output(now)) return true;
    }
  }

  void write_output(bool checkpoint) override { write_output_at(checkpoint, false); }

 private:
  /// One output: the stability check, the history row, the VTK frame (on the cadence,
  /// at checkpoints, or `frame_forced`), the checkpoint.
  void write_output_at(bool checkpoint, bool frame_forced) {
    const double now = solver_.clock().time;
    if (now == last_output_time_ && !checkpoint) return;  // written already
    last_output_time_ = now;
    if (const auto problem = check_stability(solver_, refs_, case_.mpm.speed_limit_factor)) {
      throw run::InstabilityError(
          "instability at t = {:.6g} s (step {}): {}; last good checkpoint: {} (restart from it "
          "with a smaller time step or more damping)",
          now, solver_.clock().step, *problem,
          last_checkpoint_.empty() ? "none" : last_checkpoint_.string());
    }
    history_.write(solver_, refs_.pe0);
    if (vtk_ && run::is_vtk_frame(now, vtk_every_, frame_forced || checkpoint)) {
      vtk_->write(solver_);
    }
    if (checkpoint) {
      last_checkpoint_ = options_.output_dir / run::checkpoint_file_name("mpm", now);
      write_mpm_checkpoint(last_checkpoint_, solver_, refs_, case_.name, transfer_, motion_);
      exits_.report(now);
    }
  }

  const Case& case_;
  const RunOptions& options_;
  const run::OutputSchedule& schedule_;
  MpmSolver& solver_;
  RunReferences& refs_;
  const TransferSettings& transfer_;
  const std::optional<CheckpointMotion>& motion_;
  MpmHistory& history_;
  std::optional<VtkWriter>& vtk_;
  double vtk_every_;
  Progress& progress_;
  ExitLog& exits_;
  fs::path last_checkpoint_;
  const Logger& log_;
  double last_output_time_ = -std::numeric_limits<double>::infinity();
  std::int64_t steps_ = 0;
  double particle_steps_ = 0.0;
};

/// The case's MPM settings with the command line's overrides; Error on options that
/// cannot go together.
MpmSettings settings_for(const Case& c, const RunOptions& options) {
  if (options.until && !std::isfinite(*options.until)) {
    throw Error("--until {} is not admissible (expected a finite end time in s)", *options.until);
  }
  if (options.particles_file && options.restart_file) {
    throw Error("--particles and --restart exclude each other (a restart carries its particles)");
  }
  MpmSettings settings = MpmSettings::from(c.mpm);
  settings.gravity = c.gravity;
  if (options.shape_function) settings.shape_function = *options.shape_function;
  if (options.update_scheme) settings.update_scheme = *options.update_scheme;
  if (options.sort_interval) settings.sort_interval = *options.sort_interval;
  return settings;
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
}

/// The state the time loop starts from: pure MPM's initial stresses, or the switch from
/// the FE models to the MPM ones (docs/method.md §3: Mohr–Coulomb takes the transferred
/// stresses and returns those outside its surface once; multi-yield continues the FE
/// surfaces or freezes its strength from the transferred stress); the guard's references
/// of a fresh run. A restart continues as it stopped.
void prepare_start(const Case& c, Start& start, MpmSolver& solver, double dt, const Logger& log) {
  if (start.pure_mpm) initialise_pure_mpm(c, solver, dt, log);
  if (start.fresh && !start.pure_mpm) {
    const std::size_t returned = return_to_yield_surface(solver);
    log.info("switch to the MPM models: {} of {} particles returned to the yield surface", returned,
             total_particles(solver));
  }
  if (start.fresh) set_references(c, solver, start.references, start.pure_mpm, log);
}

/// Refuses a run whose step is so small that it would never end (pure MPM's gravity
/// stage included), naming what made the step small.
void check_run_length(const Case& c, const Start& start, double duration, double dt,
                      double cell_size) {
  const double gravity_stage = start.pure_mpm && c.mpm.initial_stress != InitialStress::k0
                                   ? c.mpm.gravity_stage_duration
                                   : 0.0;
  run::check_step_count(
      gravity_stage + duration, dt,
      c.mpm.time_step > 0.0
          ? std::string("mpm.time_step is too small")
          : fmt::format("the Courant step C h / c is that small because a particle's p-wave "
                        "speed c = sqrt(M V / m) is {:.3g} m/s",
                        c.mpm.courant * cell_size / dt));
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

}  // namespace

RunSummary run_mpm(const Case& c, const RunOptions& options, const Logger& log,
                   const Ranks& ranks) {
  // ---- settings and particles: restart, particle file, or the case geometry
  const MpmSettings settings = settings_for(c, options);
  Start start = agreed(ranks, [&] {
    return options.restart_file || options.particles_file ? start_from_file(c, options, log, ranks)
                                                          : start_pure_mpm(c, settings, log, ranks);
  });
  const std::string source = options.restart_file     ? options.restart_file->string()
                             : options.particles_file ? options.particles_file->string()
                                                      : c.file.string();
  // A shaken run's grid is where the base is at the start (MpmSolver::set_base_motion).
  MpmSettings placed = settings;
  if (start.motion) {
    placed.grid.origin +=
        base_position(*start.motion, grid_motion(*start.motion), start.clock.time);
  }
  agreed(ranks, [&] {
    validate_particles(start.particles, placed, c.materials.size(), source, start.clock.frozen);
    return 0;
  });
  // Every checkpoint under a name of its own (a fresh run checkpoints its start).
  run::check_checkpoint_cadence(c.mpm.checkpoint_every, "mpm.checkpoint_every");
  run::check_checkpoint_times(c.mpm.checkpoint_times, "mpm", "mpm.checkpoint_times",
                              {start.clock.time});
  MpmSolver solver(settings, c.materials, std::move(start.particles), start.clock);
  // Pure MPM of a shaken case: the case's motion, sampled at the first step (the grid's
  // base is rigid; an FE compliant base's motion is taken as grid_base_motion does).
  if (start.pure_mpm && c.fem.motion) {
    const MotionSpec& spec = *c.fem.motion;
    start.motion =
        checkpoint_motion(make_ground_motion(spec, time_step(c.mpm, solver)),
                          std::string(to_string(spec.base)), std::string(to_string(spec.input)));
  }
  if (start.motion) {
    solver.set_base_motion(grid_motion(*start.motion), *start.motion);
    const GroundMotion& m = *solver.base_motion();
    const auto peaks = m.peaks();
    log.info(
        "base motion from {} ({} base in FE{}): t = {:.3f} → {:.3f} s, peak |a| = {:.4g} m/s², "
        "|v| = {:.4g} m/s (x); the grid's edges move with it",
        source, start.motion->base,
        start.motion->base == "compliant" ? fmt::format(", {} input", start.motion->input) : "",
        m.start_time(), m.end_time(), peaks.acceleration.x(), peaks.velocity.x());
  }
  // On several ranks, each keeps its slab's share of the particles from here on.
  solver.distribute(ranks);
  if (const Subdomain* domain = solver.subdomain()) {
    // Each part's ids were checked among themselves as they were read; now across parts.
    if (const auto duplicate = duplicate_id(solver.particles(), ranks)) {
      throw Error("{}: particles on ranks share id {}, expected unique ids", source, *duplicate);
    }
    log_slabs(log, *domain, solver);
  }
  if (start.stored_settings) {
    for (const auto& change :
         changed_settings(*start.stored_settings, settings, c.mpm.time_step, c.mpm.courant)) {
      log.warning("restart with a changed setting (the case file's is used): {}", change);
    }
  }
  RunReferences& refs = start.references;
  refs.time_step = c.mpm.time_step;
  refs.courant = c.mpm.courant;
  // The first step, for the log and the gravity stage; MpmStage takes each anew.
  const double dt = time_step(c.mpm, solver);
  log_settings(log, settings, c.mpm, dt);
  const double end_time = std::min(c.mpm.end_time, options.until.value_or(c.mpm.end_time));
  check_run_length(c, start, end_time - solver.clock().time, dt, settings.grid.cell_size);
  if (end_time < solver.clock().time) {
    throw Error("{}: the run would end at t = {} s, before its start at t = {} s{}", source,
                end_time, solver.clock().time, options.until ? " (--until)" : " (mpm.end_time)");
  }
  // A restart at its end has nothing to continue (fem-solve refuses the same); a fresh
  // run may end where it starts (--until 0: the start checkpoint only).
  if (!start.fresh &&
      !(end_time > solver.clock().time + run::OutputSchedule::tolerance(end_time))) {
    throw Error(
        "{}: the checkpoint time {:.3f} s is at or after the end time {:.3f} s{}: nothing "
        "to continue",
        source, solver.clock().time, end_time, options.until ? " (--until)" : "");
  }
  if (options.inputs_only) return {};
  prepare_start(c, start, solver, dt, log);

  // ---- outputs
  const run::OutputSchedule schedule(end_time, c.mpm.output_every, {c.mpm.checkpoint_every},
                                     c.mpm.checkpoint_times);
  fs::create_directories(options.output_dir);
  if (ranks.root()) run::remove_temporaries_of_killed_runs(options.output_dir, log);
  ranks.barrier();  // no rank writes before the root has cleared the folder
  MpmHistory history(options.output_dir / "mpm_history.csv", c.metrics);
  if (!start.fresh) history.resume(solver.clock().time, log);
  std::optional<VtkWriter> vtk;
  // The automatic cadence is that of the whole stage, from its start (t_T, or 0 for pure
  // MPM), so that a restart writes the frames the uninterrupted run writes.
  const double stage_start = start.fresh ? solver.clock().time : start.transfer.transfer_time;
  const double vtk_every = run::choose_vtk_every(options.vtk_every, c.mpm.vtk_every, stage_start,
                                                 end_time, c.mpm.output_every);
  if (options.write_vtk) {
    vtk.emplace(options.output_dir,
                start.fresh ? std::nullopt : std::optional(solver.clock().time));
    log.info("VTK frames: {}", run::describe_vtk_every(vtk_every));
  }
  Progress progress(log, "mpm", solver.clock().time, end_time);
  ExitLog exits(log, settings.particle_exit);
  MpmStage stage(c, options, schedule, solver, refs, start.transfer, start.motion, history, vtk,
                 vtk_every, progress, exits, options.restart_file.value_or(fs::path()), log);
  if (start.fresh) stage.write_start_output(schedule.is_checkpoint(solver.clock().time));

  // ---- the time loop, then the final row and mpm_final.h5
  const auto wall_start = std::chrono::steady_clock::now();
  run::drive(stage, schedule, false);
  progress.finish();
  exits.finish(solver.clock().time);
  const double wall = ranks.max(
      std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count());
  stage.write_last_output();
  write_mpm_checkpoint(options.output_dir / "mpm_final.h5", solver, refs, c.name, start.transfer,
                       start.motion);

  RunSummary summary;
  summary.steps = stage.steps();
  summary.particles = total_particles(solver);
  summary.wall_seconds = wall;
  const double particle_steps = ranks.sum(stage.particle_steps());
  summary.particle_steps_per_second = wall > 0.0 ? particle_steps / wall : 0.0;
  if (const Subdomain* domain = solver.subdomain()) log_exchanges(log, *domain, stage.steps());
  summary.end_time = solver.clock().time;
  log_memory(log, solver);
  return summary;
}

}  // namespace slide::mpm
