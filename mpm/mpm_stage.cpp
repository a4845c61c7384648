#include "mpm/mpm_stage.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <thread>

#include <omp.h>

#include "mpm/particle_generation.hpp"

namespace slide::mpm {

namespace fs = std::filesystem;

namespace {

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

/// A particle file or a restart checkpoint: its particles (this rank's part), transfer,
/// motion, and a restart's clock, references and settings.
Start start_from_file(const MpmPlan& plan, const Logger& log, const Ranks& ranks) {
  Start start;
  const bool restart = plan.run.start == run::Start::restart;
  const fs::path& path = plan.run.start_file;
  // On several ranks each reads its part of the rows (MpmSolver::distribute).
  ParticleCheckpoint file = read_particle_checkpoint(path, ranks.part());
  if (file.header.case_name != plan.source.name) {
    log.warning("{}: written for case \"{}\", run with case \"{}\" (--other-case)", path.string(),
                file.header.case_name, plan.source.name);
  }
  if (restart) {
    run::check_restart_materials(file.materials, plan.source.materials, path.string());
  } else {
    compare_materials(file.materials, plan.source.materials, path.string(), log);
  }
  start.transfer = file.transfer;
  start.motion = file.motion;
  if (restart) {
    restore(*plan.record, file.header, start.clock, start.references);
    log.info("restart from {} at t = {} s (step {})", path.string(), start.clock.time,
             start.clock.step);
  } else {
    start.clock.time = file.header.time;
    start.references.pe0 = file.header.pe0;
    log.info("{} particles from {} ({} file) at t = {} s", file.file_rows, path.string(),
             to_string(file.header.kind), file.header.time);
  }
  // The file's frozen rows are its last ones: those of this part stay last in it.
  const RowSpan rows{file.first_row, file.first_row + file.particles.count()};
  start.clock.frozen = rows.last_rows_within(file.file_rows, start.clock.frozen);
  start.file_rows = file.file_rows;
  start.first_row = file.first_row;
  start.particles = std::move(file.particles);
  return start;
}

/// Pure MPM's particles from the case geometry, with the K0 stresses of level ground when
/// the case asks for them (the gravity stage needs the solver: MpmStage::start).
Start start_pure_mpm(const MpmPlan& plan, const Logger& log, const Ranks& ranks) {
  Start start;
  const MpmCase& c = plan.source;
  const Mesh& body = *c.body;
  Particles& p = start.particles;
  // On several ranks each makes its part of the body's rows (MpmSolver::distribute).
  std::size_t body_count = 0;
  p = generate_mesh_particles(plan.settings.grid, body, c.mpm.particles_x, c.mpm.particles_y,
                              c.materials, ranks.part(), &body_count);
  log.info("pure MPM: {} particles ({} × {} per cell) in the {} elements of the case geometry",
           body_count, c.mpm.particles_x, c.mpm.particles_y, body.element_count());
  if (c.mpm.initial_stress == InitialStress::k0) {
    apply_k0_stresses(p, c.materials, mesh_surface_heights(body, p.coordinates),
                      -plan.settings.gravity.y());
    log.info("pure MPM: K0 stresses of level ground (K0 = ν/(1 − ν))");
  }
  return start;
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
void initialise_pure_mpm(const MpmSpec& spec, MpmSolver& solver, const Logger& log) {
  if (spec.initial_stress != InitialStress::k0) {
    // Elastic loading under gravity with local damping, then the state reset: the
    // equilibrium state of t = 0.
    const auto settling = solver.settle_under_gravity(
        spec.gravity_stage_duration, spec.gravity_stage_damping, time_step(spec, solver));
    log.info(
        "pure MPM: elastic gravity stage, {} s in {} steps (damping α = {}), KE {:.4g} J/m at its "
        "end",
        spec.gravity_stage_duration, settling.steps, spec.gravity_stage_damping,
        settling.kinetic_energy);
  }
  const std::size_t returned = return_to_yield_surface(solver);
  log.info(
      "pure MPM: switch to the plastic model: {} of {} particles returned to the yield surface",
      returned, total_particles(solver));
}

/// Fixes the guard's references at the start of a fresh run (collective).
void set_references(const MpmCase& c, const MpmSolver& solver, RunReferences& r, bool pure_mpm,
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

}  // namespace

Start load_start(const MpmPlan& plan, const Logger& log, const Ranks& ranks) {
  return plan.run.start == run::Start::case_geometry ? start_pure_mpm(plan, log, ranks)
                                                     : start_from_file(plan, log, ranks);
}

double time_step(const MpmSpec& spec, const MpmSolver& solver) {
  return spec.time_step > 0.0 ? spec.time_step : solver.courant_time_step(spec.courant);
}

std::size_t total_particles(const MpmSolver& solver) {
  return static_cast<std::size_t>(
      solver.ranks().sum(static_cast<double>(solver.particles().count())));
}

MpmStage::MpmStage(const MpmPlan& plan, MpmSolver& solver, Start& start, const Logger& log)
    : plan_(plan),
      solver_(solver),
      start_(start),
      log_(log),
      exits_(log, plan.settings.particle_exit),
      // The machine's processors, not this process's share of them: procs_running counts
      // the whole machine's tasks (a container's too), so a process held to a few of many
      // processors would otherwise count every other task against them.
      threads_(omp_get_max_threads(), static_cast<int>(std::thread::hardware_concurrency())) {}

void MpmStage::open_outputs(bool resume) {
  history_.emplace(plan_.run.output.folder / "mpm_history.csv", plan_.source.metrics);
  if (resume) history_->resume(time(), log_);
  if (plan_.run.output.write_vtk) {
    vtk_.emplace(plan_.run.output.folder, resume ? std::optional(time()) : std::nullopt);
    log_.info("VTK frames: {}", run::describe_vtk_every(plan_.run.output.vtk_every));
  }
}

/// The state the time loop starts from: pure MPM's initial stresses, or the switch from
/// the FE models to the MPM ones (docs/method.md §3: Mohr–Coulomb takes the transferred
/// stresses and returns those outside its surface once; multi-yield continues the FE
/// surfaces or freezes its strength from the transferred stress); the guard's references
/// of a fresh run. A restart continues as it stopped.
run::StartOutput MpmStage::start() {
  const run::Start from = plan_.run.start;
  const bool fresh = from != run::Start::restart;
  if (from == run::Start::case_geometry) initialise_pure_mpm(plan_.source.mpm, solver_, log_);
  if (from == run::Start::particle_file) {
    const std::size_t returned = return_to_yield_surface(solver_);
    log_.info("switch to the MPM models: {} of {} particles returned to the yield surface",
              returned, total_particles(solver_));
  }
  if (fresh) {
    set_references(plan_.source, solver_, start_.references, from == run::Start::case_geometry,
                   log_);
  }
  start_recorders(!fresh);
  progress_.emplace(log_, "mpm", time(), plan_.run.end_time());
  return fresh ? run::StartOutput::first : run::StartOutput::none;
}

/// The recorders, from the particles as the loop starts them (pure MPM's settled ones),
/// bounded before any of their files is written; a fresh run's first row.
void MpmStage::start_recorders(bool resume) {
  const auto& specs = plan_.source.mpm.recorders;
  if (specs.empty()) return;
  const auto folder = plan_.run.output.folder / "recorders";
  recorders_.emplace(solver_, specs, folder);
  recorders_->bound(plan_.run.end_time() - time(), time_step(plan_.source.mpm, solver_));
  if (resume) recorders_->resume(time(), log_);
  log_.info("recorders → {}: {}", folder.string(), recorders_->describe());
  if (!resume) recorders_->record(solver_);
}

bool MpmStage::advance_to(double stop) {
  const MpmSpec& spec = plan_.source.mpm;
  RunReferences& refs = start_.references;
  for (;;) {
    const double time = solver_.clock().time;
    const double step = time_step(spec, solver_);
    const bool landing = time + step >= stop;
    particle_steps_ += static_cast<double>(solver_.active_count());
    if (threads_.threads() != omp_get_max_threads()) omp_set_num_threads(threads_.threads());
    const StepReport report = solver_.step(landing ? stop - time : step);
    threads_.record_step();
    if (landing) solver_.land_on(stop);  // exactly, so restarts line up
    ++steps_;
    if (recorders_) recorders_->record(solver_);

    const double now = solver_.clock().time;
    exits_.add(report.exited, now);
    const double ke_over_pe0 = solver_.last_kinetic_energy() / refs.pe0;
    refs.rest_timer = ke_over_pe0 < spec.rest_threshold ? refs.rest_timer + (now - time) : 0.0;
    const bool at_rest = spec.rest_duration > 0.0 && refs.rest_timer >= spec.rest_duration;
    progress_->update(now, solver_.clock().step,
                      fmt::format("KE/PE0 {:.3g} Δt {:.3g} s", ke_over_pe0, step));
    if (at_rest) {
      log_.info("at rest: KE/PE0 < {} for {} s, stopping at t = {:.4f} s", spec.rest_threshold,
                spec.rest_duration, now);
      return false;
    }
    // A step that ends within the schedule's tolerance of an output time is on it.
    if (landing || plan_.run.schedule.is_output(now)) return true;
  }
}

std::optional<std::string> MpmStage::check_stability() {
  return mpm::check_stability(solver_, start_.references, plan_.source.mpm.speed_limit_factor);
}

void MpmStage::write_output(const run::OutputStep& step) {
  // The root alone writes the history: the others learn of its failure here.
  solver_.ranks().together([&] { history_->write(solver_, start_.references.pe0); });
  if (vtk_ && step.frame) vtk_->write(solver_);
  if (!step.checkpoint.empty()) {
    write_mpm_checkpoint(step.checkpoint, solver_, start_.references, plan_.source.name,
                         start_.transfer, start_.motion, plan_.fingerprint);
    exits_.report(time());
    if (recorders_) recorders_->write(solver_.ranks());
  }
}

void MpmStage::finish() {
  if (progress_) progress_->finish();
  if (threads_.steps_fewer() > 0) {
    const auto steps = static_cast<double>(threads_.steps_requested() + threads_.steps_fewer());
    log_.info(
        "threads: {} for {:.0f} % of the steps, fewer for {:.0f} % while other processes "
        "held the cores (the results do not depend on it)",
        threads_.requested(), 100.0 * static_cast<double>(threads_.steps_requested()) / steps,
        100.0 * static_cast<double>(threads_.steps_fewer()) / steps);
  }
  exits_.finish(time());
  if (recorders_) recorders_->write(solver_.ranks());
  write_mpm_checkpoint(plan_.run.output.folder / "mpm_final.h5", solver_, start_.references,
                       plan_.source.name, start_.transfer, start_.motion, plan_.fingerprint);
}

run::Work MpmStage::work() const {
  return {steps_, "particle", static_cast<std::int64_t>(total_particles(solver_)),
          solver_.ranks().sum(particle_steps_)};
}

run::OutputSizes MpmStage::output_sizes() const {
  // This rank's particle arrays: what a checkpoint stores and a frame shows.
  const auto bytes = static_cast<double>(field_data_bytes(particle_fields, solver_.particles()));
  return {bytes, bytes};
}

}  // namespace slide::mpm
