#include "mpm/mpm_run.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "common/checkpoint.hpp"
#include "common/error.hpp"
#include "common/mesh_generation.hpp"
#include "mpm/mpm_output.hpp"
#include "mpm/mpm_solver.hpp"
#include "mpm/particle_generation.hpp"

namespace slide::mpm {

namespace fs = std::filesystem;

namespace {

/// Output cadence on the simulation clock: history/VTK rows every `output_every`,
/// checkpoints at the listed times and every `checkpoint_every`, and the end. Steps are
/// shortened to land exactly on each of these times.
class Schedule {
 public:
  Schedule(const MpmSpec& spec, double end) : spec_(spec), end_(end) {}

  double end() const { return end_; }
  /// The first event strictly after t.
  double next_event(double t) const {
    double next = end_;
    next = std::min(next, next_multiple(t, spec_.output_every));
    next = std::min(next, next_multiple(t, spec_.checkpoint_every));
    for (double c : spec_.checkpoint_times) {
      if (c > t + tolerance(t)) next = std::min(next, c);
    }
    return next;
  }
  bool is_checkpoint(double t) const {
    if (is_multiple(t, spec_.checkpoint_every)) return true;
    return std::any_of(spec_.checkpoint_times.begin(), spec_.checkpoint_times.end(),
                       [&](double c) { return std::abs(c - t) <= tolerance(t); });
  }
  /// History row and VTK frame (every checkpoint is also an output step).
  bool is_output(double t) const {
    return is_multiple(t, spec_.output_every) || is_checkpoint(t) || t >= end_ - tolerance(t);
  }
  static bool is_multiple(double t, double every) {
    if (!(every > 0.0)) return false;
    return std::abs(t - std::round(t / every) * every) <= tolerance(t);
  }

 private:
  static double tolerance(double t) { return 1e-9 * std::max(1.0, std::abs(t)); }
  static double next_multiple(double t, double every) {
    if (!(every > 0.0)) return std::numeric_limits<double>::infinity();
    double k = std::floor(t / every) + 1.0;
    if (k * every <= t + tolerance(t)) k += 1.0;
    return k * every;
  }
  const MpmSpec& spec_;
  double end_;
};

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
};

void compare_materials(const MaterialTable& from_file, const MaterialTable& from_case,
                       const std::string& source, const Logger& log) {
  bool same = from_file.size() == from_case.size();
  for (std::size_t m = 0; same && m < from_file.size(); ++m) {
    same = from_file[m].name == from_case[m].name && from_file[m].model == from_case[m].model &&
           from_file[m].density == from_case[m].density;
  }
  if (!same) {
    log.warning("{}: its materials differ from the case file's; the case file's are used", source);
  }
}

Start start_from_file(const Case& c, const RunOptions& options, const Logger& log) {
  Start start;
  const bool restart = options.restart_file.has_value();
  const fs::path path = restart ? *options.restart_file : *options.particles_file;
  ParticleCheckpoint file = read_particle_checkpoint(path);
  compare_materials(file.materials, c.materials, path.string(), log);
  start.transfer = file.transfer;
  if (restart) {
    read_restart_state(file, path.string(), start.clock, start.references);
    start.stored_settings = file.solver;
    start.fresh = false;
    log.info("restart from {} at t = {} s (step {})", path.string(), start.clock.time,
             start.clock.step);
  } else {
    start.clock.time = file.header.time;
    start.references.pe0 = file.header.pe0;
    log.info("{} particles from {} ({} file) at t = {} s", file.particles.count(), path.string(),
             to_string(file.header.kind), file.header.time);
  }
  start.particles = std::move(file.particles);
  return start;
}

Start start_pure_mpm(const Case& c, const GridGeometry& grid, const Logger& log) {
  Start start;
  start.pure_mpm = true;
  start.body = build_mesh(c);
  start.particles =
      generate_mesh_particles(grid, start.body, c.mpm.particles_x, c.mpm.particles_y, c.materials);
  log.info("pure MPM: {} particles ({} × {} per cell) in the {} elements of the case geometry",
           start.particles.count(), c.mpm.particles_x, c.mpm.particles_y,
           start.body.element_count());
  return start;
}

/// The initial stresses of pure MPM (METHOD.md §5): K0 of level ground, or an elastic
/// gravity stage with damping to equilibrium; then the switch to the plastic model.
void initialise_pure_mpm(const Case& c, const Mesh& body, MpmSolver& solver, double dt,
                         const Logger& log) {
  Particles& p = solver.particles();
  if (c.mpm.initial_stress == InitialStress::k0) {
    apply_k0_stresses(p, c.materials, mesh_surface_heights(body, p.coordinates),
                      -solver.settings().gravity.y());
    log.info("pure MPM: K0 stresses of level ground (K0 = ν/(1 − ν))");
  } else {
    // Elastic loading under gravity with local damping, then velocities, displacements
    // and strains reset: the equilibrium state of t = 0.
    const NodalDamping kept = solver.settings().damping;
    solver.settings().damping.local = c.mpm.gravity_stage_damping;
    solver.use_elastic_models(true);
    std::int64_t steps = 0;
    while (solver.clock().time < c.mpm.gravity_stage_duration - 1e-12) {
      solver.step(std::min(dt, c.mpm.gravity_stage_duration - solver.clock().time));
      ++steps;
    }
    log.info(
        "pure MPM: elastic gravity stage, {} s in {} steps (damping α = {}), KE {:.4g} J/m at its "
        "end",
        c.mpm.gravity_stage_duration, steps, c.mpm.gravity_stage_damping,
        solver.energies().kinetic);
    solver.settings().damping = kept;
    solver.use_elastic_models(false);
    Particles& q = solver.particles();
    for (std::size_t k = 0; k < q.count(); ++k) {
      q.velocity[k].setZero();
      if (!q.affine_velocity.empty()) q.affine_velocity[k].setZero();
      q.displacement[k].setZero();
      q.strain[k].setZero();
      q.eps_q[k] = 0.0;
      q.state[k] = MaterialState{};
    }
    SolverClock& clock = solver.clock();
    clock.time = 0.0;
    clock.step = 0;
    clock.previous_dt = 0.0;
  }
  const std::size_t returned = solver.return_to_yield_surface();
  log.info(
      "pure MPM: switch to the plastic model: {} of {} particles returned to the yield surface",
      returned, solver.particles().count());
}

/// Fixes the guard's references at the start of a fresh run.
void set_references(const Case& c, const MpmSolver& solver, RunReferences& r, bool pure_mpm,
                    const Logger& log) {
  const Particles& p = solver.particles();
  const Energies e = solver.energies();
  const double g = solver.settings().gravity.norm();
  double y_min = std::numeric_limits<double>::infinity(), y_max = -y_min;
  for (const Vec2& x : p.coordinates) {
    y_min = std::min(y_min, x.y());
    y_max = std::max(y_max, x.y());
  }
  if (pure_mpm || !(r.pe0 != 0.0)) {
    if (!pure_mpm)
      log.warning("the particle file has pe0 = 0; PE0 = Σ m g y of its particles is used");
    r.pe0 = e.potential;
  }
  r.reference_height = c.metrics.initial_height > 0.0 ? c.metrics.initial_height : y_max - y_min;
  r.initial_energy = e.total();
  double releasable = 0.0;
  for (std::size_t k = 0; k < p.count(); ++k)
    releasable += p.mass[k] * g * (p.coordinates[k].y() - y_min);
  r.energy_scale = releasable + e.kinetic + e.elastic;
  r.rest_timer = 0.0;
}

/// The instability guard (METHOD.md §5). The energy tolerance: a stable run only loses
/// energy (friction, plasticity, damping) up to discretisation errors of the order of
/// one per cent (the vibrating bar drifts by < 0.1 %); a run that blows up multiplies
/// its energy. Growth beyond 5 % of the energy the body can release (its potential
/// energy above its lowest point, plus the initial kinetic and elastic energy) therefore
/// separates the two with a wide margin on both sides.
constexpr double energy_growth_tolerance = 0.05;

std::optional<std::string> check_stability(const MpmSolver& solver, const RunReferences& r,
                                           double speed_limit_factor) {
  const Particles& p = solver.particles();
  for (std::size_t k = 0; k < p.count(); ++k) {
    if (!p.velocity[k].allFinite() || !p.stress[k].allFinite() || !std::isfinite(p.volume[k])) {
      return fmt::format("particle {} (id {}) has a non-finite velocity, stress or volume", k,
                         p.id[k]);
    }
  }
  const double g = solver.settings().gravity.norm();
  const double limit = speed_limit_factor * std::sqrt(2.0 * g * r.reference_height);
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
  const Energies e = solver.energies();
  const double growth = e.total() - r.initial_energy;
  if (growth > energy_growth_tolerance * std::max(r.energy_scale, 1e-300)) {
    return fmt::format(
        "total energy (kinetic {:.4g} + potential + elastic {:.4g} J/m) grew by {:.4g} "
        "J/m since the start, more than {} % of the releasable energy {:.4g} J/m",
        e.kinetic, e.elastic, growth, 100 * energy_growth_tolerance, r.energy_scale);
  }
  return std::nullopt;
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

}  // namespace

RunSummary run_mpm(const Case& c, const RunOptions& options, const Logger& log) {
  // ---- settings: the case file, with the command line's overrides
  if (options.until && !std::isfinite(*options.until)) {
    throw Error("--until {} is not admissible (expected a finite end time in s)", *options.until);
  }
  MpmSettings settings = MpmSettings::from(c.mpm);
  if (options.shape_function) settings.shape_function = *options.shape_function;
  if (options.update_scheme) settings.update_scheme = *options.update_scheme;
  if (options.sort_interval) settings.sort_interval = *options.sort_interval;
  if (options.particles_file && options.restart_file) {
    throw Error("--particles and --restart exclude each other (a restart carries its particles)");
  }

  // ---- particles: restart, particle file, or the case geometry
  Start start = options.restart_file || options.particles_file
                    ? start_from_file(c, options, log)
                    : start_pure_mpm(c, settings.grid, log);
  const std::string source = options.restart_file     ? options.restart_file->string()
                             : options.particles_file ? options.particles_file->string()
                                                      : c.file.string();
  validate_particles(start.particles, settings, c.materials.size(), source, start.clock.frozen);
  MpmSolver solver(settings, c.materials, std::move(start.particles), start.clock);
  RunReferences& refs = start.references;
  // The step: the case's, or the Courant step at the particles' current densities, taken
  // anew every step (mpm/README.md, "Time step").
  const bool courant_step = !(c.mpm.time_step > 0.0);
  auto next_time_step = [&] {
    return courant_step ? solver.courant_time_step(c.mpm.courant) : c.mpm.time_step;
  };
  const double dt = next_time_step();
  if (start.stored_settings) {
    for (const auto& change :
         changed_settings(*start.stored_settings, settings, c.mpm.time_step, c.mpm.courant)) {
      log.warning("restart with a changed setting (the case file's is used): {}", change);
    }
  }
  refs.time_step = c.mpm.time_step;
  refs.courant = c.mpm.courant;
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
           c.mpm.time_step > 0.0 ? " (case)" : fmt::format(" (Courant C = {})", c.mpm.courant));

  if (start.pure_mpm) initialise_pure_mpm(c, start.body, solver, dt, log);
  if (start.fresh && !start.pure_mpm) {
    // The switch from the FE models to the MPM ones (METHOD.md §3): Mohr–Coulomb takes the
    // transferred stresses and returns those outside its surface once; multi-yield
    // continues the FE surfaces or freezes its strength from the transferred stress.
    const std::size_t returned = solver.return_to_yield_surface();
    log.info("switch to the MPM models: {} of {} particles returned to the yield surface", returned,
             solver.particles().count());
  }
  if (start.fresh) set_references(c, solver, refs, start.pure_mpm, log);

  // ---- outputs
  const double end_time = std::min(c.mpm.end_time, options.until.value_or(c.mpm.end_time));
  if (end_time < solver.clock().time) {
    throw Error("{}: the run would end at t = {} s, before its start at t = {} s{}", source,
                end_time, solver.clock().time, options.until ? " (--until)" : " (mpm.end_time)");
  }
  const Schedule schedule(c.mpm, end_time);
  fs::create_directories(options.output_dir);
  const std::optional<double> resume =
      start.fresh ? std::nullopt : std::optional(solver.clock().time);
  HistoryWriter history(options.output_dir / "mpm_history.csv", c.metrics, resume);
  std::optional<VtkWriter> vtk;
  if (options.write_vtk) vtk.emplace(options.output_dir, resume);
  fs::path last_checkpoint = options.restart_file.value_or(fs::path());
  double last_output_time = -std::numeric_limits<double>::infinity();
  auto write_outputs = [&](bool checkpoint) {
    if (solver.clock().time == last_output_time && !checkpoint) return;  // written already
    last_output_time = solver.clock().time;
    if (const auto problem = check_stability(solver, refs, c.mpm.speed_limit_factor)) {
      throw InstabilityError(
          "instability at t = {:.6g} s (step {}): {}; last good checkpoint: {} (restart from it "
          "with a smaller time step or more damping)",
          solver.clock().time, solver.clock().step, *problem,
          last_checkpoint.empty() ? "none" : last_checkpoint.string());
    }
    history.write(solver, refs.pe0);
    if (vtk && (options.vtk_every <= 0.0 ||
                Schedule::is_multiple(solver.clock().time, options.vtk_every) || checkpoint)) {
      vtk->write(solver);
    }
    if (checkpoint) {
      last_checkpoint = checkpoint_path(options.output_dir, solver.clock().time);
      write_mpm_checkpoint(last_checkpoint, solver, refs, c.name, start.transfer);
    }
  };
  if (start.fresh) write_outputs(schedule.is_checkpoint(solver.clock().time));

  // ---- the time loop
  const double start_time = solver.clock().time;
  Progress progress(log, "mpm", start_time, end_time);
  const auto wall_start = std::chrono::steady_clock::now();
  std::int64_t steps = 0;
  double particle_steps = 0.0;
  ExitLog exits(log, settings.particle_exit);
  bool at_rest = false;
  while (solver.clock().time < end_time - 1e-9 * std::max(1.0, end_time)) {
    const double time = solver.clock().time;
    const double event = schedule.next_event(time);
    const double step = next_time_step();
    const bool landing = time + step >= event;
    particle_steps += static_cast<double>(solver.active_count());
    const StepReport report = solver.step(landing ? event - time : step);
    if (landing) solver.clock().time = event;  // exactly, so restarts line up
    ++steps;

    exits.add(report.exited, solver.clock().time);
    const double ke_over_pe0 = solver.last_kinetic_energy() / refs.pe0;
    refs.rest_timer =
        ke_over_pe0 < c.mpm.rest_threshold ? refs.rest_timer + (solver.clock().time - time) : 0.0;
    at_rest = c.mpm.rest_duration > 0.0 && refs.rest_timer >= c.mpm.rest_duration;

    const double now = solver.clock().time;
    if (schedule.is_output(now) || at_rest) write_outputs(schedule.is_checkpoint(now));
    if (schedule.is_checkpoint(now)) exits.report(now);
    progress.update(now, solver.clock().step,
                    fmt::format("KE/PE0 {:.3g} Δt {:.3g} s", ke_over_pe0, step));
    if (at_rest) {
      log.info("at rest: KE/PE0 < {} for {} s, stopping at t = {:.4f} s", c.mpm.rest_threshold,
               c.mpm.rest_duration, now);
      break;
    }
  }
  progress.finish();
  exits.finish(solver.clock().time);
  const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  write_outputs(false);
  write_mpm_checkpoint(options.output_dir / "mpm_final.h5", solver, refs, c.name, start.transfer);

  RunSummary summary;
  summary.steps = steps;
  summary.particles = solver.particles().count();
  summary.wall_seconds = wall;
  summary.particle_steps_per_second = wall > 0.0 ? particle_steps / wall : 0.0;
  summary.end_time = solver.clock().time;
  const auto memory = solver.memory();
  const auto per_particle = [&](std::size_t bytes) {
    return static_cast<double>(bytes) /
           static_cast<double>(std::max<std::size_t>(summary.particles, 1));
  };
  log.info(
      "memory: {:.0f} B/particle in particle arrays + {:.0f} B/particle sort peak + grid and "
      "windows {:.2f} MB ({:.0f} B/particle) = {:.0f} B/particle",
      per_particle(memory.particle_arrays), per_particle(memory.sort_peak),
      static_cast<double>(memory.grid) / 1e6, per_particle(memory.grid),
      per_particle(memory.total()));
  return summary;
}

}  // namespace slide::mpm
