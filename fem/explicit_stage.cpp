#include "fem/explicit_stage.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "common/base/error.hpp"
#include "common/input/motion.hpp"
#include "common/io/atomic_file.hpp"
#include "fem/element_kernels.hpp"
#include "fem/geostatic.hpp"
#include "fem/mesh_quality.hpp"
#include "fem/pore_fluid.hpp"

namespace slide::fem {

namespace {

std::string format_time(std::optional<double> t) {
  return t ? fmt::format("{:.3f}", *t) : std::string("none");
}

/// "; damping: Rayleigh α_M = …, β_K = … (from ξ …), local α = …", or nothing undamped.
std::string damping_summary(const DampingSpec& damping) {
  if (!(damping.rayleigh_mass > 0.0 || damping.rayleigh_stiffness > 0.0 || damping.local > 0.0)) {
    return {};
  }
  std::string text = fmt::format("; damping: Rayleigh α_M = {:.6g} 1/s, β_K = {:.6g} s",
                                 damping.rayleigh_mass, damping.rayleigh_stiffness);
  if (damping.ratio) {
    text += fmt::format(" (from ξ = {} at {} and {} Hz)", damping.ratio->ratio,
                        damping.ratio->frequencies[0], damping.ratio->frequencies[1]);
  }
  return text + fmt::format(", local α = {}", damping.local);
}

}  // namespace

// ----------------------------------------------------------------------------- outputs

void FemOutputs::open(bool resume, double time) {
  const std::filesystem::path& folder = plan_.run.output.folder;
  history_.emplace(folder / "fem_history.csv", model_.fluid.active());
  if (plan_.run.output.write_vtk) {
    vtk_.emplace(folder);
    log_.info("VTK frames: {}", run::describe_vtk_every(plan_.run.output.vtk_every));
  }
  if (!resume) return;
  history_->resume(time, log_);
  if (vtk_) vtk_->resume(time);
  for (const auto& row : history_->rows()) zone_exited_ = zone_exited_ || !row.inside_zone();
}

void FemOutputs::write_checkpoint(const FemState& state, const FemRecord& record,
                                  const std::optional<CheckpointMotion>& motion,
                                  const std::filesystem::path& file, double pe0) {
  const FemSpec& fem = plan_.source.fem;
  CheckpointContext context;
  context.case_name = plan_.source.name;
  context.pe0 = pe0;
  context.friction_coefficient = fem.friction_coefficient;
  context.solver = run::merged(write_record(record), plan_.fingerprint);
  FemCheckpoint checkpoint = make_checkpoint(model_, state, context);
  checkpoint.boundary_conditions = node_set_conditions(
      model_.mesh, record.stage == geostatic_stage ? fem.geostatic_boundaries : [&] {
        // fem.failure.boundaries, without the side rollers that tied or viscous sides replace.
        BoundaryTable table = fem.failure_boundaries;
        if (fem.motion && fem.motion->lateral != LateralBoundary::boundaries) {
          for (const char* side : {"left", "right"}) {
            if (table.contains(side)) table[side] = BoundaryCondition::free;
          }
        }
        return table;
      }());
  checkpoint.motion = motion;
  slide::write_checkpoint(file, checkpoint);
  written_.push_back(file);
  log_.info("t = {:.3f} s: wrote {}", state.time, file.string());
}

bool FemOutputs::written_this_run(const std::filesystem::path& file) const {
  for (const auto& written : written_) {
    if (written == file) return true;
  }
  return false;
}

template <class Write>
void FemOutputs::track_zone(const HistoryRow& row, const FemState& state, Write&& write) {
  if (zone_exited_) return;
  if (row.inside_zone()) {
    if (plan_.checkpoint_at_zone_exit) zone_state_ = state;
    return;
  }
  zone_exited_ = true;
  log_.info(
      "t = {:.3f} s: left the recommended transfer zone ((|J_t|/|J_0|)_avg = {:.4f}, "
      "εq,avg = {:.4f})",
      state.time, row.jacobian_ratio_avg, row.eps_q_avg);
  if (!zone_state_) return;
  const auto file = plan_.run.output.folder / run::checkpoint_file_name("fem", zone_state_->time);
  // A regular checkpoint of that time, or fem_t0.000.h5 at t = 0, already serves.
  if (written_this_run(file) || zone_state_->time <= run::OutputSchedule::tolerance(0.0)) {
    log_.info("zone-exit checkpoint: {} (already written)", file.string());
  } else {
    write(*zone_state_, file);
  }
  zone_state_.reset();
}

void FemOutputs::keep_zone_state(const FemState& state) {
  if (plan_.checkpoint_at_zone_exit && !zone_exited_) zone_state_ = state;
}

// ----------------------------------------------------------------------------- set-up

ExplicitStage::ExplicitStage(const FemPlan& plan, const FemModel& model, const Logger& log)
    : plan_(plan), model_(model), log_(log), outputs_(plan, model, log) {
  const FemSpec& fem = plan.source.fem;
  if (plan.restart) {
    state_ = state_from_checkpoint(model, *plan.restart, plan.run.start_file);
    guard_.pe0 = plan.restart->header.pe0;
  } else {
    state_ = make_rest_state(model);
  }
  time_step_ = fem.time_step > 0.0
                   ? fem.time_step
                   : damped_time_step(courant_time_step(model, model.mesh.nodes, 1.0), fem.courant,
                                      fem.damping.rayleigh_stiffness,
                                      courant_time_step(model, model.mesh.nodes, 1.0,
                                                        model.elements.skeleton_wave_speed));
  if (!fem.failure_stage) return;
  // A run too long to finish (a huge stiffness, a tiny fixed step) and a bad motion are
  // refused now, before the geostatic checkpoint is written.
  make_solver();
  choose_time_step(false);
  if (fem.motion) {
    shaking_.motion = make_ground_motion(*fem.motion, time_step_, plan.source.motion_until);
  }
  make_recorders();
  if (!plan.restart) return;
  const std::string& kinematics = plan.record.kinematics;
  if (!kinematics.empty() && kinematics != to_string(fem.kinematics)) {
    log.warning("{}: written with {} kinematics, continued with {}", plan.run.start_file.string(),
                kinematics, to_string(fem.kinematics));
  }
  log.info("restart from {} (t = {:.3f} s, step {}, stage {})", plan.run.start_file.string(),
           state_.time, state_.step, plan.record.stage);
}

void ExplicitStage::make_solver() {
  std::vector<ConstitutiveModel> models;
  for (const auto& material : model_.materials) models.push_back(ConstitutiveModel::from(material));
  const FemSpec& fem = plan_.source.fem;
  solver_.emplace(model_,
                  make_constraints(model_.mesh, failure_boundaries(), "fem.failure.boundaries"),
                  fem.friction_coefficient, damping_of(fem.damping), std::move(models));
}

/// fem.failure.boundaries, without the side rollers that tied or viscous sides replace.
BoundaryTable ExplicitStage::failure_boundaries() const {
  const FemSpec& fem = plan_.source.fem;
  BoundaryTable table = fem.failure_boundaries;
  if (fem.motion && fem.motion->lateral != LateralBoundary::boundaries) {
    for (const char* side : {"left", "right"}) {
      if (table.contains(side)) table[side] = BoundaryCondition::free;
    }
  }
  return table;
}

/// Why the step is as small as it is, for the refusal of a run that would take too many.
std::string ExplicitStage::small_step_reason(bool fluid_binds, double damping_reduction) const {
  const FemSpec& fem = plan_.source.fem;
  if (fem.time_step > 0.0) return "fem.time_step is too small";
  if (fluid_binds) {
    return fmt::format(
        "the pore-pressure diffusion limit S_e/ΣT (h²/(4D) on squares, D = (k/γ_w) K_f/n) is "
        "{:.3g} s (lower fem.water.bulk_modulus or a conductivity)",
        solver_->fluid_time_step());
  }
  if (damping_reduction < 0.5) {
    return fmt::format("fem.damping.rayleigh_stiffness = {:g} s lowers the stable step × {:.3g}",
                       fem.damping.rayleigh_stiffness, damping_reduction);
  }
  double fastest = 0.0;  // the largest p-wave speed, m/s (undrained in saturated elements)
  for (const double c : model_.elements.wave_speed) fastest = std::max(fastest, c);
  return fmt::format(
      "the Courant step is that small because an element's p-wave speed is {:.3g} "
      "m/s{}",
      fastest, model_.fluid.active() ? " (undrained: sqrt((M + K_f/n)/ρ))" : "");
}

/// The step: fixed, or the Courant step lowered by the stiffness-proportional damping
/// (docs/method.md §3; the stability limit is the same at C = 1). Refuses a step that would
/// need more steps than any run could take (it would hang the program), naming the cause.
/// `announce`: log the step (and warn of a fixed step above the limit).
void ExplicitStage::choose_time_step(bool announce) {
  const FemSpec& fem = plan_.source.fem;
  const DampingSpec& damping = fem.damping;
  const double critical_step = solver_->critical_time_step(state_);
  const double skeleton_step = solver_->skeleton_time_step(state_);
  const double mechanical_step =
      damped_time_step(critical_step, fem.courant, damping.rayleigh_stiffness, skeleton_step);
  const double reduction = mechanical_step / (fem.courant * critical_step);
  // With pore water, the Darcy term's forward Euler may bind instead (fem/pore_fluid.hpp).
  const double fluid_step = solver_->fluid_time_step();
  const double courant_step = std::min(mechanical_step, fluid_step);
  time_step_ = fem.time_step > 0.0 ? fem.time_step : courant_step;
  run::check_step_count(plan_.run.end_time() - state_.time, time_step_,
                        small_step_reason(fluid_step < mechanical_step, reduction));
  if (!announce) return;
  if (fem.time_step > 0.0 && fem.time_step > mechanical_step / fem.courant) {
    log_.warning("fem.time_step = {:.4g} s exceeds the stability limit {:.4g} s (C = 1{})",
                 fem.time_step, mechanical_step / fem.courant,
                 damping.rayleigh_stiffness > 0.0 ? ", with β_K" : "");
  }
  if (fem.time_step > 0.0 && fem.time_step > fluid_step) {
    log_.warning("fem.time_step = {:.4g} s exceeds the pore-pressure diffusion limit {:.4g} s",
                 fem.time_step, fluid_step);
  }
  std::string step_kind = fem.time_step > 0.0 ? "fixed"
                          : fluid_step < mechanical_step
                              ? fmt::format(
                                    "pore-pressure diffusion S_e/ΣT; Courant C = {} "
                                    "would give {:.4g} s",
                                    fem.courant, mechanical_step)
                              : fmt::format("Courant C = {}", fem.courant);
  if (damping.rayleigh_stiffness > 0.0) {
    const double ratio = critical_step / skeleton_step;
    step_kind += fmt::format(
        ", × {:.4g} for β_K: ξ_max = {:.4g} at ω_max = 2/dt_c = {:.4g} rad/s{}", reduction,
        damping.rayleigh_stiffness / critical_step * (ratio * ratio), 2.0 / critical_step,
        skeleton_step > critical_step
            ? fmt::format(" (β_K damps the skeleton, whose ω_max is {:.4g} rad/s)",
                          2.0 / skeleton_step)
            : "");
  }
  log_.info("failure stage: {} kinematics, dt = {:.4g} s ({}), t = {:.3f} → {:.3f} s{}",
            to_string(fem.kinematics), time_step_, step_kind, state_.time, plan_.run.end_time(),
            damping_summary(damping));
}

/// The step `state` takes next, the one rule of the stage: fixed, the Courant step of its
/// current geometry (updated Lagrangian), else the constant one of the reference geometry.
double ExplicitStage::step_for(const FemState& state) {
  const FemSpec& fem = plan_.source.fem;
  if (fem.time_step > 0.0) return fem.time_step;
  if (solver_ && model_.kinematics == Kinematics::updated_lagrangian) {
    return solver_->stable_time_step(state, fem.courant);
  }
  return time_step_;
}

// ----------------------------------------------------------------------------- start

void ExplicitStage::open_outputs(bool resume) {
  outputs_.open(resume, state_.time);
}

run::StartOutput ExplicitStage::start() {
  if (model_.fluid.active()) log_pore_water();
  // PM4Sand's contraction rate, when the case reader calibrated it (docs/method.md §10).
  for (const Material& m : model_.materials) {
    if (!m.uses(MaterialModel::pm4sand) || std::isnan(m.pm4sand.calibrated_crr)) continue;
    log_.info(
        "PM4Sand: material \"{}\": D_R = {}, h_po = {:.4g} calibrated: 3 % strain in {:.2f} "
        "cycles of undrained simple shear at CSR = CRR = {:.4g}",
        m.name, m.pm4sand.relative_density, m.pm4sand.contraction_rate, m.pm4sand.calibrated_cycles,
        m.pm4sand.calibrated_crr);
  }
  if (!plan_.restart) {
    run_geostatic_stage();
    // A case without a failure stage: the geostatic state's row and frame.
    if (!plan_.source.fem.failure_stage) return run::StartOutput::first;
  }
  return start_failure_stage();
}

void ExplicitStage::log_pore_water() const {
  const PoreFluid& fluid = model_.fluid;
  const auto saturated = std::ranges::count(fluid.saturated, std::uint8_t{1});
  const auto drained =
      std::ranges::count_if(fluid.faces, [](const FluidFace& f) { return f.to < 0; });
  log_.info(
      "pore water: table at y = {} m, ρ_w = {} kg/m³, K_f = {:.4g} Pa, tension limit {:.4g} Pa; "
      "{} of {} elements saturated (u–p, one pressure each), {} faces between them, {} drained "
      "(on or above the table, in a drained set, or under the reservoir)",
      fluid.level_point.y(), fluid.density, fluid.bulk_modulus, fluid.tension_limit, saturated,
      model_.element_count(), static_cast<std::ptrdiff_t>(fluid.faces.size()) - drained, drained);
  // Skempton's B of an undrained element, 1/(1 + n K/K_f) with incompressible grains: the
  // share of an isotropic load the water takes. A lowered K_f (the speed knob) lowers it.
  constexpr double water_bulk_modulus = 2.2e9;
  for (const Material& m : model_.materials) {
    if (!m.saturable()) continue;
    const double skeleton = m.youngs_modulus / (3.0 * (1.0 - 2.0 * m.poisson_ratio));
    const auto skempton = [&](double kf) { return 1.0 / (1.0 + m.porosity * skeleton / kf); };
    log_.info(
        "pore water: material \"{}\": n = {}, k = ({:.3g}, {:.3g}) m/s, Skempton B = {:.4f}{}",
        m.name, m.porosity, m.conductivity_x, m.conductivity_y, skempton(fluid.bulk_modulus),
        fluid.bulk_modulus < water_bulk_modulus
            ? fmt::format(" (K_f lowered from water's 2.2 GPa, where B = {:.4f})",
                          skempton(water_bulk_modulus))
            : std::string());
  }
}

namespace {

/// The geostatic stage's tied side pairs ([fem.geostatic] lateral = "tied"), or none.
std::vector<std::pair<Index, Index>> geostatic_ties(const FemModel& model, const FemSpec& fem) {
  if (!fem.geostatic_tied_sides) return {};
  return pair_sides(model, "fem.geostatic.lateral = \"tied\"");
}

}  // namespace

void ExplicitStage::run_geostatic_stage() {
  const NodalConstraints constraints = make_constraints(
      model_.mesh, plan_.source.fem.geostatic_boundaries, "fem.geostatic.boundaries");
  const GeostaticReport report =
      solve_geostatic(model_, constraints, state_, geostatic_ties(model_, plan_.source.fem));
  guard_.pe0 =
      compute_energies(model_, model_.reference, state_, state_.velocity, model_.mesh.nodes)
          .potential;
  log_.info(
      "geostatic stage: {} elements ({}), {} equations, max |u| = {:.4g} m (reset to 0), "
      "relative residual {:.2g}, PE0 = {:.6g} J/m",
      model_.element_count(), to_string(model_.mesh.element_type), report.equations,
      report.max_displacement, report.relative_residual, guard_.pe0);
  write_checkpoint(state_, geostatic_stage,
                   plan_.run.output.folder / run::checkpoint_file_name("fem", 0.0));
}

/// The switch to the failure models (from the geostatic state), the shaking, the
/// recorders, the guard's references and the step; then the stage's first row: at t = 0
/// after the switch (fem_t0.000.h5 holds the geostatic state before it); a restart keeps
/// the row its checkpoint's run wrote, or writes it when the history lacks it.
run::StartOutput ExplicitStage::start_failure_stage() {
  const bool switch_models = plan_.switches_models();
  start_shaking(switch_models);
  start_recorders(!switch_models);
  if (switch_models) {
    const std::size_t returned = solver_->return_to_yield_surface(state_);
    log_.info("failure stage: {} of {} Gauss points returned to the yield surface at the switch",
              returned, model_.gauss_count());
  }
  set_guard_limits(switch_models);
  choose_time_step(true);
  guard_.on = true;
  progress_.emplace(log_, "failure stage", state_.time, plan_.run.end_time());
  const auto& rows = outputs_.history().rows();
  if (rows.empty() ||
      rows.back().time < state_.time - run::OutputSchedule::tolerance(state_.time)) {
    return switch_models ? run::StartOutput::first : run::StartOutput::row;
  }
  outputs_.keep_zone_state(state_);
  return run::StartOutput::none;
}

/// The boundaries of the shaking from the start of the failure stage (docs/method.md §8).
/// Released supports keep their static reactions: those of the state when it is still
/// the geostatic one, else of the geostatic equilibrium solved again (a restart).
void ExplicitStage::start_shaking(bool from_geostatic_state) {
  if (!shaking_.motion) return;
  const FemSpec& fem = plan_.source.fem;
  const MotionSpec& spec = *fem.motion;
  std::vector<Vec2> reactions;
  if (from_geostatic_state) {
    reactions = support_reactions(model_, state_);
  } else {
    FemState geostatic = make_rest_state(model_);
    solve_geostatic(
        model_, make_constraints(model_.mesh, fem.geostatic_boundaries, "fem.geostatic.boundaries"),
        geostatic, geostatic_ties(model_, fem));
    reactions = support_reactions(model_, geostatic);
  }
  shaking_.boundary = make_seismic_boundary(model_, spec, *shaking_.motion, reactions);
  solver_->set_seismic(&shaking_.boundary);
  if (plan_.record.boundary_work) solver_->set_boundary_work(*plan_.record.boundary_work);
  const GroundMotion& motion = *shaking_.motion;
  const GroundMotion::Peaks peaks = motion.peaks();
  log_.info(
      "motion: t = {:.3f} → {:.3f} s, sampled every {:.4g} s; peaks |a| = {:.4g}, {:.4g} m/s², "
      "|v| = {:.4g}, {:.4g} m/s, |u| = {:.4g}, {:.4g} m (x, y){}",
      motion.start_time(), motion.end_time(), motion.step(), peaks.acceleration.x(),
      peaks.acceleration.y(), peaks.velocity.x(), peaks.velocity.y(), peaks.displacement.x(),
      peaks.displacement.y(),
      spec.baseline_correction
          ? fmt::format("; baseline correction removed {:.3g} → {:.3g} m/s² (x)",
                        motion.correction_start().x(), motion.correction_end().x())
          : std::string("; no baseline correction"));
  if (motion.cut()) {
    // Kept to the last end time of the case's runs; a record much longer than that is
    // more often a wrong file or time unit than a plan, so it is said louder.
    const double kept = motion.end_time() - motion.start_time();
    const double dropped = motion.record_end_time() - motion.end_time();
    const std::string line = fmt::format(
        "motion: the record runs to t = {:.4g} s, past the case's runs (fem-solve's and "
        "mpm.end_time, {:.4g} s): its samples are kept to t = {:.4g} s, {:.3g} s of {:.3g} s "
        "(its baseline correction spans the whole record)",
        motion.record_end_time(), plan_.source.motion_until, motion.end_time(), kept,
        kept + dropped);
    if (dropped > kept) {
      log_.warning("{}", line);
    } else {
      log_.info("{}", line);
    }
  }
  log_.info("{}", describe(shaking_.boundary, spec));
  write_text_atomically(plan_.run.output.folder / "motion.csv", motion_csv(motion));
}

/// The recorders, checked (node sets, names) and bounded before any file is written.
void ExplicitStage::make_recorders() {
  const FemSpec& fem = plan_.source.fem;
  if (fem.recorders.empty()) return;
  const GroundMotion* motion = shaking_.motion ? &*shaking_.motion : nullptr;
  const bool rigid = motion && fem.motion->base == SeismicBase::rigid;
  std::vector<Index> base_nodes;
  if (motion && !rigid) {
    for (const NodeSet& set : model_.mesh.node_sets) {
      if (set.name == "base") base_nodes = set.nodes;
    }
  }
  auto& recorders = outputs_.recorders();
  recorders =
      std::make_unique<Recorders>(model_, fem.recorders, plan_.run.output.folder / "recorders",
                                  rigid ? motion : nullptr, std::move(base_nodes));
  recorders->bound(plan_.run.end_time() - state_.time, time_step_);
}

void ExplicitStage::start_recorders(bool resume) {
  auto& recorders = outputs_.recorders();
  if (!recorders) return;
  if (resume) recorders->resume(state_.time, log_);
  log_.info("recorders → {}: {}", (plan_.run.output.folder / "recorders").string(),
            recorders->describe());
}

/// The guard's references: the state at the start of the stage, or on restart the
/// reference the first run fixed (carried by the checkpoint).
void ExplicitStage::set_guard_limits(bool fresh_stage) {
  measures_.step = -1;  // the switch changed the stresses at the same time and step
  const Measures& m = measure();
  GuardLimits& limits = guard_.limits;
  limits.speed_limit = run::speed_limit(plan_.source.fem.speed_limit_factor, gravity_acceleration,
                                        model_.extent.height);
  const Energies& energies = m.energies;
  limits.energy.initial_energy = total_energy(energies);
  limits.energy.energy_scale = releasable_potential_energy(model_) + energies.elastic +
                               energies.hourglass + energies.kinetic;
  if (fresh_stage) return;
  if (const auto reference = plan_.record.energy()) {
    limits.energy = *reference;
  } else {
    log_.warning("the checkpoint has no energy reference; the guard starts from its state");
  }
}

// ----------------------------------------------------------------------------- steps

bool ExplicitStage::advance_to(double stop) {
  const auto& recorders = outputs_.recorders();
  while (state_.time < stop) {
    const double dt = step_for(state_);
    const double remaining = stop - state_.time;
    const bool last = remaining <= dt * (1.0 + 1e-6);
    const double step = last ? remaining : dt;
    const Index inverted = solver_->step(state_, step);
    if (inverted >= 0) stop_at_inversion(inverted, state_.time + step);
    ++steps_;
    last_step_ = step;
    if (last) state_.time = stop;
    if (recorders) recorders->record(state_, step);
    if (last) break;
    if ((steps_ & 63) == 0) progress_->update(state_.time, state_.step);
  }
  return true;  // an inversion ends the run by an Error, never early
}

/// Updated Lagrangian: the step to `failing_time` would invert `element`. The last good
/// state (t_n) is written and the run stops with an Error naming both.
void ExplicitStage::stop_at_inversion(Index element, double failing_time) {
  if (const auto problem = check_stability()) {
    throw Error(
        "updated Lagrangian: element {} inverts (det J ≤ 0) in the step from t = {:.6f} s "
        "to {:.6f} s after an instability: {}; stopped, the last good checkpoint is {}",
        element, state_.time, failing_time, *problem,
        last_checkpoint().empty() ? "none" : last_checkpoint().string());
  }
  auto file = plan_.run.output.folder / run::checkpoint_file_name("fem", state_.time);
  for (const auto& written : outputs_.written()) {
    if (written == file) {
      file = plan_.run.output.folder /
             fmt::format("fem_t{:.6f}.h5", state_.time);  // finer than the schedule's
    }
  }
  write_checkpoint(state_, failure_stage, file);
  throw Error(
      "updated Lagrangian: element {} inverts (det J ≤ 0) in the step from t = {:.6f} s to "
      "{:.6f} s; stopped, the last good state is in {}",
      element, state_.time, failing_time, file.string());
}

// ----------------------------------------------------------------------------- outputs

/// The current state's coordinates, synchronised velocity and energies, computed once
/// per output step for the guard and the history row.
const ExplicitStage::Measures& ExplicitStage::measure() {
  Measures& m = measures_;
  if (m.time == state_.time && m.step == state_.step) return m;
  update_coordinates(model_, state_, m.coordinates);
  if (solver_ && guard_.on) {
    solver_->synchronised_velocity(state_, last_step_, m.synchronised);
  } else {
    m.synchronised = state_.velocity;
  }
  m.energies = compute_energies(model_, energy_geometry(m), state_, m.synchronised, m.coordinates);
  m.time = state_.time;
  m.step = state_.step;
  return m;
}

/// The geometry the energies integrate with, on the measures' coordinates: the kernels'.
const ElementGeometry& ExplicitStage::energy_geometry(Measures& m) {
  if (model_.kinematics == Kinematics::small_strain) return model_.reference;
  compute_geometry(model_, m.coordinates, m.current_geometry);
  return m.current_geometry;
}

/// E = KE + (PE − PE_0) + stored energy, less the work the boundaries of a shaken stage
/// did on the body (zero otherwise): what the energy guard watches.
double ExplicitStage::total_energy(const Energies& energies) const {
  const double work = solver_ ? solver_->boundary_work() : 0.0;
  return energies.kinetic + (energies.potential - guard_.pe0) + energies.elastic +
         energies.hourglass - work;
}

std::optional<std::string> ExplicitStage::check_stability() {
  if (!guard_.on) return std::nullopt;
  const Measures& m = measure();
  std::string diagnosis =
      fem::check_stability(model_, state_, m.coordinates, total_energy(m.energies), guard_.limits);
  if (diagnosis.empty()) return std::nullopt;
  return diagnosis;
}

HistoryRow ExplicitStage::history_row(const ElementQuality& quality) {
  const Energies& energies = measure().energies;
  const QualitySummary summary = summarise(quality);
  const double pe0 = guard_.pe0;
  HistoryRow row;
  row.time = state_.time;
  row.kinetic_energy = energies.kinetic;
  row.pe0 = pe0;
  row.ke_over_pe0 = pe0 != 0.0 ? energies.kinetic / pe0 : std::numeric_limits<double>::quiet_NaN();
  row.jacobian_ratio_min = summary.jacobian_ratio_min;
  row.jacobian_ratio_avg = summary.jacobian_ratio_avg;
  row.eps_q_avg = summary.eps_q_avg;
  row.eps_q_max = summary.eps_q_max;
  row.n_elements_yielding = summary.n_elements_yielding;
  row.area_ratio = summary.area_ratio;
  row.scaled_jacobian_min = summary.scaled_jacobian_min;
  row.scaled_jacobian_avg = summary.scaled_jacobian_avg;
  if (model_.fluid.active()) {
    std::vector<double> ratio;
    pore_pressure_ratio(model_, state_, ratio);
    row.pore_pressure_ratio_max = *std::ranges::max_element(ratio);
    const std::vector<double> element_ratio = element_pore_pressure_ratio(model_, ratio);
    row.high_pore_pressure_area = 0.0;
    for (std::size_t e = 0; e < element_ratio.size(); ++e) {
      if (element_ratio[e] >= high_pore_pressure_ratio) {
        row.high_pore_pressure_area += model_.elements.volume_reference[e];
      }
    }
  }
  return row;
}

void ExplicitStage::write_output(const run::OutputStep& step) {
  const Measures& m = measure();
  const ElementQuality quality = evaluate_quality(model_, state_, m.coordinates);
  const HistoryRow row = history_row(quality);
  report_inversion(row, quality);
  outputs_.history().add(row);
  if (VtkSeries* vtk = outputs_.vtk(); vtk && step.frame) {
    vtk->write(model_, state_, m.coordinates, quality);
  }
  if (!step.checkpoint.empty()) {
    write_checkpoint(state_, failure_stage, step.checkpoint);
    if (outputs_.recorders()) outputs_.recorders()->write();
  }
  if (guard_.on) {
    outputs_.track_zone(row, state_, [&](const FemState& state, const std::filesystem::path& file) {
      write_checkpoint(state, failure_stage, file);
    });
  }
  if (progress_) {
    progress_->update(state_.time, state_.step, fmt::format("KE/PE0 {:.4f}", row.ke_over_pe0));
  }
}

/// The first output with an inverted element (as fem2mpm counts it, is_inverted; the
/// previous row may come from the run before a restart) is logged.
void ExplicitStage::report_inversion(const HistoryRow& row, const ElementQuality& quality) {
  const auto& rows = outputs_.history().rows();
  if (!row.inverted() || (!rows.empty() && rows.back().inverted())) return;
  Index inverted = 0;
  for (const std::uint8_t flag : quality.inverted) inverted += flag;
  log_.info(
      "t = {:.3f} s: {} element(s) inverted (det J < 0 at a corner or zero area; fem2mpm refuses "
      "them), (|J_t|/|J_0|)_min = {:.3f}, area ratio {:.4f}{}",
      state_.time, inverted, row.jacobian_ratio_min, row.area_ratio,
      model_.kinematics == Kinematics::small_strain ? " (small strain: the run goes on)" : "");
}

FemRecord ExplicitStage::record_of(const FemState& state, const char* stage) {
  const FemSpec& fem = plan_.source.fem;
  FemRecord record;
  record.stage = stage;
  record.kinematics = to_string(model_.kinematics);
  record.element_type = to_string(model_.mesh.element_type);
  record.courant = fem.courant;
  // The step the state would take next (the geostatic state's as the failure stage
  // would take it).
  record.time_step = step_for(state);
  record.hourglass_coefficient = model_.hourglass_coefficient;
  if (record.stage != geostatic_stage) {
    record.set_energy(guard_.limits.energy);
    if (shaking_.motion) record.boundary_work = solver_->boundary_work();
  }
  return record;
}

void ExplicitStage::write_checkpoint(const FemState& state, const char* stage,
                                     const std::filesystem::path& file) {
  std::optional<CheckpointMotion> motion;
  if (shaking_.motion) {
    const MotionSpec& spec = *plan_.source.fem.motion;
    motion = checkpoint_motion(*shaking_.motion, std::string(to_string(spec.base)),
                               std::string(to_string(spec.input)));
    motion->base_time = state.time;
    motion->base_displacement = mean_base_displacement(state);
  }
  outputs_.write_checkpoint(state, record_of(state, stage), motion, file, guard_.pe0);
  note_checkpoint(file);
}

/// Where the base is: the motion's displacement for a rigid base (its nodes on it, or
/// sliding on it), the mean displacement of the base nodes for a compliant one (which
/// includes the drift of the whole model on its dashpots).
Vec2 ExplicitStage::mean_base_displacement(const FemState& state) const {
  if (plan_.source.fem.motion->base == SeismicBase::rigid) {
    return shaking_.motion->displacement(state.time);
  }
  Vec2 sum = Vec2::Zero();
  std::size_t count = 0;
  for (const NodeSet& set : model_.mesh.node_sets) {
    if (set.name != "base") continue;
    for (const Index n : set.nodes) sum += state.displacement[static_cast<std::size_t>(n)];
    count += set.nodes.size();
  }
  return count > 0 ? Vec2(sum / static_cast<double>(count)) : Vec2::Zero();
}

// ----------------------------------------------------------------------------- end

void ExplicitStage::finish() {
  if (progress_) progress_->finish();
  if (outputs_.recorders()) outputs_.recorders()->write();
}

run::Work ExplicitStage::work() const {
  return {steps_, "element", model_.element_count(),
          static_cast<double>(model_.element_count() * steps_)};
}

run::OutputSizes ExplicitStage::output_sizes() const {
  // What a checkpoint stores; a frame shows about as much.
  const double bytes = fem_checkpoint_bytes(state_, model_.mesh);
  return {bytes, bytes};
}

namespace {

/// Zone, inversion and KE peak from the whole history (also the rows before a restart).
void read_history(const std::vector<HistoryRow>& rows, FemRunSummary& summary) {
  bool exited = false;
  for (const auto& row : rows) {
    if (!exited && row.inside_zone()) summary.last_time_in_zone = row.time;
    if (!exited && !row.inside_zone()) {
      exited = true;
      summary.zone_exit_time = row.time;
    }
    if (!summary.first_time_inverted && row.inverted()) summary.first_time_inverted = row.time;
    if (!summary.first_time_jacobian_ratio_negative && row.jacobian_ratio_min < 0.0) {
      summary.first_time_jacobian_ratio_negative = row.time;
    }
    if (row.ke_over_pe0 > summary.ke_over_pe0_max) {
      summary.ke_over_pe0_max = row.ke_over_pe0;
      summary.ke_over_pe0_max_time = row.time;
    }
    summary.ke_over_pe0_end = row.ke_over_pe0;
  }
}

std::string at(double t) {
  return fmt::format("t = {:.3f} s", t);
}

/// "last inside at t = …, left at t = …" and the like: the recommended zone over the run.
std::string zone_text(const FemRunSummary& summary) {
  if (summary.last_time_in_zone && summary.zone_exit_time) {
    return fmt::format("last inside at {}, left at {}", at(*summary.last_time_in_zone),
                       at(*summary.zone_exit_time));
  }
  if (summary.last_time_in_zone) {
    return fmt::format("inside at every output step, to {}", at(*summary.last_time_in_zone));
  }
  if (summary.zone_exit_time) return fmt::format("outside from {} on", at(*summary.zone_exit_time));
  return "no output step";
}

/// When an element first inverted, or that none did.
std::string inversion_text(const FemRunSummary& summary) {
  const auto first = [](const std::optional<double>& t) {
    return t ? fmt::format("first at {}", at(*t)) : std::string("never");
  };
  if (!summary.first_time_inverted && !summary.first_time_jacobian_ratio_negative) {
    return "no element inverted (det J > 0 at every corner at every output step)";
  }
  return fmt::format(
      "element inverted (det J < 0 at a corner or zero area) {}, (|J_t|/|J_0|)_min < 0 {}",
      first(summary.first_time_inverted), first(summary.first_time_jacobian_ratio_negative));
}

}  // namespace

FemRunSummary ExplicitStage::summary(const run::RunResult& result) const {
  FemRunSummary summary;
  summary.steps = steps_;
  summary.elements = model_.element_count();
  summary.end_time = state_.time;
  summary.checkpoints = outputs_.written();
  summary.wall_seconds = result.wall_seconds;
  read_history(outputs_.history().rows(), summary);
  for (const Vec2& u : state_.displacement) {
    summary.max_displacement = std::max(summary.max_displacement, u.norm());
  }
  if (plan_.source.fem.failure_stage) {
    log_.info("recommended transfer zone ((|J_t|/|J_0|)_avg ≥ {}, εq,avg ≤ {}): {}",
              zone_jacobian_ratio_avg_min, zone_eps_q_avg_max, zone_text(summary));
    log_.info("{}; KE/PE0 peak {:.5f} at {}", inversion_text(summary), summary.ke_over_pe0_max,
              at(summary.ke_over_pe0_max_time));
  }
  const std::string text = fmt::format(
      "# fem-solve summary of case {} (times in s; docs/method.md §3)\n"
      "element = {}\nkinematics = {}\nend_time = {:.6g}\nsteps = {}\nelements = {}\n"
      "last_time_in_zone = {}\nzone_exit_time = {}\nfirst_time_jacobian_ratio_negative = {}\n"
      "first_time_inverted = {}\nke_over_pe0_max = {:.6g}\nke_over_pe0_max_time = {:.6g}\n"
      "wall_s = {:.3f}\n",
      plan_.source.name, to_string(model_.mesh.element_type), to_string(model_.kinematics),
      summary.end_time, state_.step, summary.elements, format_time(summary.last_time_in_zone),
      format_time(summary.zone_exit_time), format_time(summary.first_time_jacobian_ratio_negative),
      format_time(summary.first_time_inverted), summary.ke_over_pe0_max,
      summary.ke_over_pe0_max_time, summary.wall_seconds);
  write_text_atomically(plan_.run.output.folder / "fem_summary.txt", text);
  return summary;
}

}  // namespace slide::fem
