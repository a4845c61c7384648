#include "fem/fem_solver.hpp"

#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <string>

#include <fmt/format.h>

#include "common/base/error.hpp"
#include "common/input/mesh_generation.hpp"
#include "common/input/motion.hpp"
#include "common/io/atomic_file.hpp"
#include "common/io/checkpoint.hpp"
#include "common/run/output_schedule.hpp"
#include "common/run/stability_guard.hpp"
#include "common/run/stage.hpp"
#include "fem/element_kernels.hpp"
#include "fem/explicit_dynamics.hpp"
#include "fem/fem_model.hpp"
#include "fem/fem_output.hpp"
#include "fem/geostatic.hpp"
#include "fem/mesh_quality.hpp"
#include "fem/recorders.hpp"
#include "fem/seismic_boundary.hpp"
#include "fem/stability_guard.hpp"

namespace slide::fem {

namespace {

constexpr const char* geostatic_stage = "geostatic";
constexpr const char* failure_stage = "failure";
std::string format_time(std::optional<double> t) {
  return t ? fmt::format("{:.3f}", *t) : std::string("none");
}

std::optional<double> setting_double(const SolverSettings& settings, const std::string& key) {
  const auto found = settings.find(key);
  if (found == settings.end()) return std::nullopt;
  if (const auto* value = std::get_if<double>(&found->second)) return *value;
  return std::nullopt;
}

std::string setting_string(const SolverSettings& settings, const std::string& key) {
  const auto found = settings.find(key);
  if (found == settings.end()) return {};
  if (const auto* value = std::get_if<std::string>(&found->second)) return *value;
  return {};
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

/// One run of fem-solve, from a case (fresh) or from a checkpoint (restart).
class FemRun final : public run::Stage {
 public:
  FemRun(const Case& c, const FemOptions& options, const Logger& logger);
  FemRunSummary execute();

 private:
  void prepare_fresh();
  void prepare_restart();
  void create_outputs(bool resume);
  void run_geostatic_stage();
  void start_failure_stage(bool switch_models);
  void set_guard_limits(bool fresh_stage);
  void make_failure_solver();
  BoundaryTable failure_boundaries() const;
  void choose_time_step(bool announce);
  void prepare_motion();
  void start_shaking(bool from_geostatic_state);
  void start_recorders(bool resume);
  Vec2 mean_base_displacement(const FemState& state) const;
  // run::Stage: the failure stage's steps and outputs.
  double time() const override { return state_.time; }
  bool advance_to(double stop) override;
  void write_output(bool checkpoint) override { output(checkpoint); }
  void output(bool checkpoint);
  HistoryRow diagnose(const ElementQuality& quality);
  void track_zone(const HistoryRow& row);
  void stop_at_inversion(Index element, double failing_time);
  void write_fem_checkpoint(const FemState& state, const std::string& stage,
                            const std::filesystem::path& file);
  bool written_this_run(const std::filesystem::path& file) const;
  double total_energy(const Energies& energies) const;
  const ElementGeometry& energy_geometry();
  FemRunSummary finish();

  Case case_;
  FemOptions options_;
  const Logger& logger_;
  std::chrono::steady_clock::time_point started_ = std::chrono::steady_clock::now();

  std::unique_ptr<FemModel> model_;
  FemState state_;
  std::unique_ptr<ExplicitSolver> solver_;
  run::OutputSchedule schedule_;
  std::unique_ptr<FemHistory> history_;
  std::unique_ptr<VtkSeries> vtk_;
  double vtk_every_ = 0.0;  ///< s between frames (0: every output step)
  std::unique_ptr<Progress> progress_;

  std::string restart_stage_;
  SolverSettings restart_settings_;
  bool failure_started_ = false;
  double pe0_ = 0.0;
  double time_step_ = 0.0;  ///< Courant or fixed step (small strain: constant)
  double last_step_ = 0.0;  ///< length of the step that led to the current state
  GuardLimits limits_;
  Index steps_ = 0;
  std::vector<std::filesystem::path> written_;
  std::filesystem::path last_checkpoint_;

  // Recommended transfer zone: the state at the last output inside it.
  bool zone_exited_ = false;
  std::optional<FemState> zone_state_;

  // Shaking (docs/method.md §8): the processed motion and what it does at the boundaries.
  std::optional<GroundMotion> motion_;
  SeismicBoundary seismic_;
  std::unique_ptr<Recorders> recorders_;

  // Scratch of the output steps.
  std::vector<Vec2> coordinates_;
  std::vector<Vec2> synchronised_;
  ElementGeometry current_geometry_;
};

FemRun::FemRun(const Case& c, const FemOptions& options, const Logger& logger)
    : case_(c),
      options_(options),
      logger_(logger),
      schedule_(options.until.value_or(c.fem.end_time), c.fem.output_every,
                {c.fem.checkpoint_every, options.checkpoint_every}, c.fem.checkpoint_times) {
  if (options_.element) case_.mesh.element_type = *options_.element;
  if (options_.kinematics) case_.fem.kinematics = *options_.kinematics;
  if (case_.fem.failure_stage && !(schedule_.end_time() > 0.0)) {
    throw Error("--until {} is not admissible (expected an end time > 0 s)", schedule_.end_time());
  }
  if (options_.checkpoint_every < 0.0) {
    throw Error("--checkpoint-every {} is not admissible (expected ≥ 0 s)",
                options_.checkpoint_every);
  }
  // Every checkpoint under a name of its own (fem_t0.000.h5 is the geostatic state).
  run::check_checkpoint_cadence(options_.checkpoint_every, "--checkpoint-every");
  run::check_checkpoint_cadence(case_.fem.checkpoint_every, "fem.checkpoint_every");
  run::check_checkpoint_times(case_.fem.checkpoint_times, "fem", "fem.checkpoint_times", {0.0});
  vtk_every_ = run::choose_vtk_every(options_.vtk_every, case_.fem.vtk_every, 0.0,
                                     schedule_.end_time(), case_.fem.output_every);
}

FemRunSummary FemRun::execute() {
  if (options_.restart) {
    prepare_restart();
  } else {
    prepare_fresh();
  }
  if (options_.inputs_only) return {};
  // From the geostatic state (fem_t0.000.h5, written before the t = 0 outputs) the
  // failure stage starts afresh: its outputs too, so that t = 0 rows and frames a killed
  // run left incomplete are written again.
  create_outputs(options_.restart.has_value() && restart_stage_ != geostatic_stage);
  if (!options_.restart) {
    run_geostatic_stage();
    if (!case_.fem.failure_stage) {
      output(false);
      return finish();
    }
  }
  start_failure_stage(!options_.restart || restart_stage_ == geostatic_stage);
  // The end is a checkpoint: a later run continues from it.
  run::drive(*this, schedule_, true);
  return finish();
}

void FemRun::prepare_fresh() {
  // Everything that can reject the input happens before the first file is written.
  Mesh mesh = build_mesh(case_);
  make_constraints(mesh, case_.fem.geostatic_boundaries, "fem.geostatic.boundaries");
  if (case_.fem.failure_stage) {
    make_constraints(mesh, case_.fem.failure_boundaries, "fem.failure.boundaries");
  }
  model_ =
      std::make_unique<FemModel>(make_model(std::move(mesh), case_.materials, case_.fem.kinematics,
                                            case_.fem.hourglass_coefficient, case_.gravity));
  state_ = make_rest_state(*model_);
  if (case_.fem.failure_stage) {
    // A run too long to finish (a huge stiffness, a tiny fixed step) is refused now, not
    // after the geostatic checkpoint has been written.
    make_failure_solver();
    choose_time_step(false);
    prepare_motion();
  }
}

void FemRun::prepare_restart() {
  const std::filesystem::path& file = *options_.restart;
  const CheckpointHeader header = read_checkpoint_header(file);
  if (header.kind != CheckpointKind::fem) {
    throw Error("{}: checkpoint kind is \"{}\", fem-solve restarts from a kind \"fem\" checkpoint",
                file.string(), to_string(header.kind));
  }
  FemCheckpoint checkpoint = read_fem_checkpoint(file);
  if (checkpoint.header.case_name != case_.name) {
    throw Error("{}: written for case \"{}\", not for case \"{}\" of {}", file.string(),
                checkpoint.header.case_name, case_.name, case_.file.string());
  }
  if (checkpoint.mesh.element_type != case_.mesh.element_type) {
    throw Error("{}: the checkpoint has {} elements but the case asks for {}", file.string(),
                to_string(checkpoint.mesh.element_type), to_string(case_.mesh.element_type));
  }
  run::check_restart_materials(checkpoint.materials, case_.materials, file.string());
  restart_stage_ = setting_string(checkpoint.solver, "stage");
  if (restart_stage_ != geostatic_stage && restart_stage_ != failure_stage) {
    throw Error("{}: /solver attribute stage is \"{}\" (expected \"geostatic\" or \"failure\")",
                file.string(), restart_stage_);
  }
  if (!case_.fem.failure_stage) {
    throw Error(
        "{}: the case has no failure stage (fem.failure_stage = false), nothing to "
        "continue",
        file.string());
  }
  if (!(checkpoint.header.time < schedule_.end_time()) ||
      schedule_.is_end(checkpoint.header.time)) {
    throw Error("{}: the checkpoint time {:.3f} s is at or after the end time {:.3f} s",
                file.string(), checkpoint.header.time, schedule_.end_time());
  }
  validate_mesh(checkpoint.mesh, file.string(), case_.materials.size());
  make_constraints(checkpoint.mesh, case_.fem.failure_boundaries, "fem.failure.boundaries");
  model_ =
      std::make_unique<FemModel>(make_model(checkpoint.mesh, case_.materials, case_.fem.kinematics,
                                            case_.fem.hourglass_coefficient, case_.gravity));
  state_ = state_from_checkpoint(*model_, checkpoint, file);
  make_failure_solver();
  choose_time_step(false);  // refuses a run too long to finish before any file is touched
  prepare_motion();
  pe0_ = checkpoint.header.pe0;
  restart_settings_ = checkpoint.solver;
  last_checkpoint_ = file;
  const std::string kinematics = setting_string(checkpoint.solver, "kinematics");
  if (!kinematics.empty() && kinematics != to_string(case_.fem.kinematics)) {
    logger_.warning("{}: written with {} kinematics, continued with {}", file.string(), kinematics,
                    to_string(case_.fem.kinematics));
  }
  logger_.info("restart from {} (t = {:.3f} s, step {}, stage {})", file.string(), state_.time,
               state_.step, restart_stage_);
}

void FemRun::create_outputs(bool resume) {
  std::filesystem::create_directories(options_.output_dir);
  run::remove_temporaries_of_killed_runs(options_.output_dir, logger_);
  history_ = std::make_unique<FemHistory>(options_.output_dir / "fem_history.csv");
  if (options_.write_vtk) {
    vtk_ = std::make_unique<VtkSeries>(options_.output_dir);
    logger_.info("VTK frames: {}", run::describe_vtk_every(vtk_every_));
  }
  if (!resume) return;
  history_->resume(state_.time, logger_);
  if (vtk_) vtk_->resume(state_.time);
  for (const auto& row : history_->rows()) zone_exited_ = zone_exited_ || !row.inside_zone();
}

void FemRun::run_geostatic_stage() {
  const NodalConstraints constraints =
      make_constraints(model_->mesh, case_.fem.geostatic_boundaries, "fem.geostatic.boundaries");
  const GeostaticReport report = solve_geostatic(*model_, constraints, state_);
  pe0_ = compute_energies(*model_, model_->reference, state_, state_.velocity, model_->mesh.nodes)
             .potential;
  logger_.info(
      "geostatic stage: {} elements ({}), {} equations, max |u| = {:.4g} m (reset to 0), "
      "relative residual {:.2g}, PE0 = {:.6g} J/m",
      model_->element_count(), to_string(model_->mesh.element_type), report.equations,
      report.max_displacement, report.relative_residual, pe0_);
  write_fem_checkpoint(state_, geostatic_stage,
                       options_.output_dir / run::checkpoint_file_name("fem", 0.0));
}

void FemRun::make_failure_solver() {
  std::vector<ConstitutiveModel> models;
  for (const auto& material : model_->materials)
    models.push_back(ConstitutiveModel::from(material));
  solver_ = std::make_unique<ExplicitSolver>(
      *model_, make_constraints(model_->mesh, failure_boundaries(), "fem.failure.boundaries"),
      case_.fem.friction_coefficient, damping_of(case_.fem.damping), std::move(models));
}

/// fem.failure.boundaries, without the side rollers that tied or viscous sides replace.
BoundaryTable FemRun::failure_boundaries() const {
  BoundaryTable table = case_.fem.failure_boundaries;
  const auto& motion = case_.fem.motion;
  if (motion && motion->lateral != LateralBoundary::boundaries) {
    for (const char* side : {"left", "right"}) {
      if (table.contains(side)) table[side] = BoundaryCondition::free;
    }
  }
  return table;
}

/// The case's motion, sampled at the failure stage's step (refused before any file is
/// written when its file or its numbers are bad).
void FemRun::prepare_motion() {
  if (!case_.fem.motion) return;
  motion_ = make_ground_motion(*case_.fem.motion, time_step_);
}

/// The boundaries of the shaking from the start of the failure stage (docs/method.md §8).
/// Released supports keep their static reactions: those of the state when it is still
/// the geostatic one, else of the geostatic equilibrium solved again (a restart).
void FemRun::start_shaking(bool from_geostatic_state) {
  if (!motion_) return;
  const MotionSpec& spec = *case_.fem.motion;
  std::vector<Vec2> reactions;
  if (from_geostatic_state) {
    reactions = support_reactions(*model_, state_);
  } else {
    FemState geostatic = make_rest_state(*model_);
    solve_geostatic(
        *model_,
        make_constraints(model_->mesh, case_.fem.geostatic_boundaries, "fem.geostatic.boundaries"),
        geostatic);
    reactions = support_reactions(*model_, geostatic);
  }
  seismic_ = make_seismic_boundary(*model_, spec, *motion_, reactions);
  solver_->set_seismic(&seismic_);
  if (const auto work = setting_double(restart_settings_, "boundary_work")) {
    solver_->set_boundary_work(*work);
  }
  const GroundMotion::Peaks peaks = motion_->peaks();
  logger_.info(
      "motion: t = {:.3f} → {:.3f} s, sampled every {:.4g} s; peaks |a| = {:.4g}, {:.4g} m/s², "
      "|v| = {:.4g}, {:.4g} m/s, |u| = {:.4g}, {:.4g} m (x, y){}",
      motion_->start_time(), motion_->end_time(), motion_->step(), peaks.acceleration.x(),
      peaks.acceleration.y(), peaks.velocity.x(), peaks.velocity.y(), peaks.displacement.x(),
      peaks.displacement.y(),
      spec.baseline_correction
          ? fmt::format("; baseline correction removed {:.3g} → {:.3g} m/s² (x)",
                        motion_->correction_start().x(), motion_->correction_end().x())
          : std::string("; no baseline correction"));
  logger_.info("{}", describe(seismic_, spec));
  write_text_atomically(options_.output_dir / "motion.csv", motion_csv(*motion_));
}

/// Where the base is: the motion's displacement for a rigid base (its nodes on it, or
/// sliding on it), the mean displacement of the base nodes for a compliant one (which
/// includes the drift of the whole model on its dashpots).
Vec2 FemRun::mean_base_displacement(const FemState& state) const {
  if (case_.fem.motion->base == SeismicBase::rigid) return motion_->displacement(state.time);
  Vec2 sum = Vec2::Zero();
  std::size_t count = 0;
  for (const NodeSet& set : model_->mesh.node_sets) {
    if (set.name != "base") continue;
    for (const Index n : set.nodes) sum += state.displacement[static_cast<std::size_t>(n)];
    count += set.nodes.size();
  }
  return count > 0 ? Vec2(sum / static_cast<double>(count)) : Vec2::Zero();
}

void FemRun::start_recorders(bool resume) {
  if (case_.fem.recorders.empty()) return;
  const bool rigid = motion_ && case_.fem.motion->base == SeismicBase::rigid;
  std::vector<Index> base_nodes;
  if (motion_ && !rigid) {
    for (const NodeSet& set : model_->mesh.node_sets) {
      if (set.name == "base") base_nodes = set.nodes;
    }
  }
  recorders_ =
      std::make_unique<Recorders>(*model_, case_.fem.recorders, options_.output_dir / "recorders",
                                  rigid ? &*motion_ : nullptr, std::move(base_nodes));
  if (resume) recorders_->resume(state_.time, logger_);
  logger_.info("recorders → {}: {}", (options_.output_dir / "recorders").string(),
               recorders_->describe());
}

void FemRun::start_failure_stage(bool switch_models) {
  start_shaking(switch_models);
  start_recorders(!switch_models);
  if (switch_models) {
    const std::size_t returned = solver_->return_to_yield_surface(state_);
    logger_.info("failure stage: {} of {} Gauss points returned to the yield surface at the switch",
                 returned, model_->gauss_count());
  }
  set_guard_limits(switch_models);
  choose_time_step(true);
  failure_started_ = true;
  progress_ =
      std::make_unique<Progress>(logger_, "failure stage", state_.time, schedule_.end_time());

  // The first row: at t = 0 after the switch (fem_t0.000.h5 holds the geostatic state
  // before it); a restart keeps the row its checkpoint's run wrote.
  const auto& rows = history_->rows();
  if (rows.empty() ||
      rows.back().time < state_.time - run::OutputSchedule::tolerance(state_.time)) {
    output(false);
  } else if (options_.checkpoint_at_zone_exit && !zone_exited_) {
    zone_state_ = state_;
  }
}

/// The guard's references: the state at the start of the stage, or on restart the
/// reference the first run fixed (carried by the checkpoint).
void FemRun::set_guard_limits(bool fresh_stage) {
  update_coordinates(*model_, state_, coordinates_);
  const Energies energies =
      compute_energies(*model_, energy_geometry(), state_, state_.velocity, coordinates_);
  limits_.speed_limit =
      run::speed_limit(case_.fem.speed_limit_factor, gravity_acceleration, model_->height);
  limits_.energy.initial_energy = total_energy(energies);
  limits_.energy.energy_scale = releasable_potential_energy(*model_) + energies.elastic +
                                energies.hourglass + energies.kinetic;
  if (fresh_stage) return;
  // "initial_total_energy" in the checkpoints of fem-solve before the shared run loop.
  auto initial = setting_double(restart_settings_, "initial_energy");
  if (!initial) initial = setting_double(restart_settings_, "initial_total_energy");
  const auto scale = setting_double(restart_settings_, "energy_scale");
  if (initial && scale) {
    // A NaN reference would switch the energy guard off (no comparison with NaN fails).
    if (!std::isfinite(*initial) || !std::isfinite(*scale) || !(*scale > 0.0)) {
      throw Error(
          "{}: /solver energy reference initial_energy = {}, energy_scale = {} (expected "
          "finite values, energy_scale > 0)",
          last_checkpoint_.string(), *initial, *scale);
    }
    limits_.energy.initial_energy = *initial;
    limits_.energy.energy_scale = *scale;
  } else {
    logger_.warning("the checkpoint has no energy reference; the guard starts from its state");
  }
}

/// The step: fixed, or the Courant step lowered by the stiffness-proportional damping
/// (docs/method.md §3; the stability limit is the same at C = 1). Refuses a step that would
/// need more steps than any run could take (it would hang the program), naming the cause.
/// `announce`: log the step (and warn of a fixed step above the limit).
void FemRun::choose_time_step(bool announce) {
  const DampingSpec& damping = case_.fem.damping;
  const double critical_step = solver_->critical_time_step(state_);
  const double courant_step =
      damped_time_step(critical_step, case_.fem.courant, damping.rayleigh_stiffness);
  const double reduction = courant_step / (case_.fem.courant * critical_step);
  time_step_ = case_.fem.time_step > 0.0 ? case_.fem.time_step : courant_step;
  double fastest = 0.0;  // the largest p-wave speed, m/s
  for (const double c : model_->wave_speed) fastest = std::max(fastest, c);
  run::check_step_count(
      schedule_.end_time() - state_.time, time_step_,
      case_.fem.time_step > 0.0 ? std::string("fem.time_step is too small")
      : reduction < 0.5
          ? fmt::format("fem.damping.rayleigh_stiffness = {:g} s lowers the stable step × {:.3g}",
                        damping.rayleigh_stiffness, reduction)
          : fmt::format("the Courant step is that small because a material's p-wave speed "
                        "sqrt(M/ρ) is {:.3g} m/s",
                        fastest));
  if (!announce) return;
  if (case_.fem.time_step > 0.0 && case_.fem.time_step > courant_step / case_.fem.courant) {
    logger_.warning("fem.time_step = {:.4g} s exceeds the stability limit {:.4g} s (C = 1{})",
                    case_.fem.time_step, courant_step / case_.fem.courant,
                    damping.rayleigh_stiffness > 0.0 ? ", with β_K" : "");
  }
  std::string step_kind =
      case_.fem.time_step > 0.0 ? "fixed" : fmt::format("Courant C = {}", case_.fem.courant);
  if (damping.rayleigh_stiffness > 0.0) {
    step_kind +=
        fmt::format(", × {:.4g} for β_K: ξ_max = {:.4g} at ω_max = 2/dt_c = {:.4g} rad/s",
                    reduction, damping.rayleigh_stiffness / critical_step, 2.0 / critical_step);
  }
  logger_.info("failure stage: {} kinematics, dt = {:.4g} s ({}), t = {:.3f} → {:.3f} s{}",
               to_string(case_.fem.kinematics), time_step_, step_kind, state_.time,
               schedule_.end_time(), damping_summary(damping));
}

bool FemRun::advance_to(double stop) {
  const bool courant_every_step =
      model_->kinematics == Kinematics::updated_lagrangian && !(case_.fem.time_step > 0.0);
  while (state_.time < stop) {
    // Updated Lagrangian: the Courant step of the current geometry, with the β_K reduction.
    const double dt =
        courant_every_step ? solver_->stable_time_step(state_, case_.fem.courant) : time_step_;
    const double remaining = stop - state_.time;
    const bool last = remaining <= dt * (1.0 + 1e-6);
    const double step = last ? remaining : dt;
    const Index inverted = solver_->step(state_, step);
    if (inverted >= 0) stop_at_inversion(inverted, state_.time + step);
    ++steps_;
    last_step_ = step;
    if (last) state_.time = stop;
    if (recorders_) recorders_->record(state_, step);
    if (last) break;
    if ((steps_ & 63) == 0) progress_->update(state_.time, state_.step);
  }
  return true;  // an inversion ends the run by an Error, never early
}

/// The geometry the energies integrate with, on `coordinates_`: the kernels' own.
const ElementGeometry& FemRun::energy_geometry() {
  if (model_->kinematics == Kinematics::small_strain) return model_->reference;
  compute_geometry(*model_, coordinates_, current_geometry_);
  return current_geometry_;
}

/// E = KE + (PE − PE_0) + stored energy, less the work the boundaries of a shaken stage
/// did on the body (zero otherwise): what the energy guard watches.
double FemRun::total_energy(const Energies& energies) const {
  const double work = solver_ ? solver_->boundary_work() : 0.0;
  return energies.kinetic + (energies.potential - pe0_) + energies.elastic + energies.hourglass -
         work;
}

HistoryRow FemRun::diagnose(const ElementQuality& quality) {
  if (solver_) {
    solver_->synchronised_velocity(state_, last_step_, synchronised_);
  } else {
    synchronised_ = state_.velocity;
  }
  const Energies energies =
      compute_energies(*model_, energy_geometry(), state_, synchronised_, coordinates_);
  if (failure_started_) {
    const std::string diagnosis =
        check_stability(*model_, state_, coordinates_, total_energy(energies), limits_);
    if (!diagnosis.empty()) {
      throw Error("{}; stopped, the last good checkpoint is {}", diagnosis,
                  last_checkpoint_.empty() ? "none" : last_checkpoint_.string());
    }
  }
  const QualitySummary summary = summarise(quality);
  HistoryRow row;
  row.time = state_.time;
  row.kinetic_energy = energies.kinetic;
  row.pe0 = pe0_;
  row.ke_over_pe0 =
      pe0_ != 0.0 ? energies.kinetic / pe0_ : std::numeric_limits<double>::quiet_NaN();
  row.jacobian_ratio_min = summary.jacobian_ratio_min;
  row.jacobian_ratio_avg = summary.jacobian_ratio_avg;
  row.eps_q_avg = summary.eps_q_avg;
  row.eps_q_max = summary.eps_q_max;
  row.n_elements_yielding = summary.n_elements_yielding;
  row.area_ratio = summary.area_ratio;
  row.scaled_jacobian_min = summary.scaled_jacobian_min;
  row.scaled_jacobian_avg = summary.scaled_jacobian_avg;
  return row;
}

void FemRun::output(bool checkpoint) {
  update_coordinates(*model_, state_, coordinates_);
  const ElementQuality quality = evaluate_quality(*model_, state_, coordinates_);
  const HistoryRow row = diagnose(quality);
  // Inverted as fem2mpm counts it (is_inverted); the previous row may come from the run
  // before a restart.
  const auto& rows = history_->rows();
  const bool newly_inverted = row.inverted() && (rows.empty() || !rows.back().inverted());
  history_->add(row);
  const bool start_checkpoint_or_end =
      checkpoint || state_.time == 0.0 || schedule_.is_end(state_.time);
  if (vtk_ && run::is_vtk_frame(state_.time, vtk_every_, start_checkpoint_or_end)) {
    vtk_->write(*model_, state_, coordinates_, quality);
  }
  if (checkpoint) {
    write_fem_checkpoint(state_, failure_stage,
                         options_.output_dir / run::checkpoint_file_name("fem", state_.time));
    if (recorders_) recorders_->write();
  }
  if (newly_inverted) {
    Index inverted = 0;
    for (const std::uint8_t flag : quality.inverted) inverted += flag;
    logger_.info(
        "t = {:.3f} s: {} element(s) inverted (det J < 0 at a corner or zero area; fem2mpm refuses "
        "them), "
        "(|J_t|/|J_0|)_min = {:.3f}, area ratio {:.4f}{}",
        state_.time, inverted, row.jacobian_ratio_min, row.area_ratio,
        model_->kinematics == Kinematics::small_strain ? " (small strain: the run goes on)" : "");
  }
  if (failure_started_) track_zone(row);
  if (progress_) {
    progress_->update(state_.time, state_.step, fmt::format("KE/PE0 {:.4f}", row.ke_over_pe0));
  }
}

/// Keeps the state of the last output inside the recommended zone (with
/// --checkpoint-at-zone-exit) and writes it when the zone is left.
void FemRun::track_zone(const HistoryRow& row) {
  if (zone_exited_) return;
  if (row.inside_zone()) {
    if (options_.checkpoint_at_zone_exit) zone_state_ = state_;
    return;
  }
  zone_exited_ = true;
  logger_.info(
      "t = {:.3f} s: left the recommended transfer zone ((|J_t|/|J_0|)_avg = {:.4f}, "
      "εq,avg = {:.4f})",
      state_.time, row.jacobian_ratio_avg, row.eps_q_avg);
  if (!zone_state_) return;
  const auto file = options_.output_dir / run::checkpoint_file_name("fem", zone_state_->time);
  // A regular checkpoint of that time, or fem_t0.000.h5 at t = 0, already serves.
  if (written_this_run(file) || zone_state_->time <= run::OutputSchedule::tolerance(0.0)) {
    logger_.info("zone-exit checkpoint: {} (already written)", file.string());
  } else {
    write_fem_checkpoint(*zone_state_, failure_stage, file);
  }
  zone_state_.reset();
}

void FemRun::stop_at_inversion(Index element, double failing_time) {
  // `state_` is still the last good state, at t_n.
  update_coordinates(*model_, state_, coordinates_);
  const Energies energies =
      compute_energies(*model_, energy_geometry(), state_, state_.velocity, coordinates_);
  const std::string diagnosis =
      check_stability(*model_, state_, coordinates_, total_energy(energies), limits_);
  if (!diagnosis.empty()) {
    throw Error(
        "updated Lagrangian: element {} inverts (det J ≤ 0) in the step from t = {:.6f} s "
        "to {:.6f} s after an {}; stopped, the last good checkpoint is {}",
        element, state_.time, failing_time, diagnosis,
        last_checkpoint_.empty() ? "none" : last_checkpoint_.string());
  }
  auto file = options_.output_dir / run::checkpoint_file_name("fem", state_.time);
  if (written_this_run(file))
    file = options_.output_dir /
           fmt::format("fem_t{:.6f}.h5", state_.time);  // finer than the schedule's
  write_fem_checkpoint(state_, failure_stage, file);
  throw Error(
      "updated Lagrangian: element {} inverts (det J ≤ 0) in the step from t = {:.6f} s to "
      "{:.6f} s; stopped, the last good state is in {}",
      element, state_.time, failing_time, file.string());
}

bool FemRun::written_this_run(const std::filesystem::path& file) const {
  for (const auto& written : written_) {
    if (written == file) return true;
  }
  return false;
}

void FemRun::write_fem_checkpoint(const FemState& state, const std::string& stage,
                                  const std::filesystem::path& file) {
  CheckpointContext context;
  context.case_name = case_.name;
  context.pe0 = pe0_;
  const bool geostatic = stage == geostatic_stage;
  context.boundary_conditions = node_set_conditions(
      model_->mesh, geostatic ? case_.fem.geostatic_boundaries : failure_boundaries());
  context.friction_coefficient = case_.fem.friction_coefficient;
  context.solver["stage"] = stage;
  context.solver["kinematics"] = std::string(to_string(model_->kinematics));
  context.solver["element_type"] = std::string(to_string(model_->mesh.element_type));
  context.solver["courant"] = case_.fem.courant;
  // The step the state would take next: fixed, or the Courant step of its geometry
  // (lowered by the stiffness damping, as the failure stage takes it).
  context.solver["time_step"] =
      case_.fem.time_step > 0.0 ? case_.fem.time_step
      : solver_                 ? solver_->stable_time_step(state, case_.fem.courant)
                : damped_time_step(courant_time_step(*model_, model_->mesh.nodes, 1.0),
                                   case_.fem.courant, case_.fem.damping.rayleigh_stiffness);
  context.solver["hourglass_coefficient"] = model_->hourglass_coefficient;
  if (!geostatic) {
    context.solver["initial_energy"] = limits_.energy.initial_energy;
    context.solver["energy_scale"] = limits_.energy.energy_scale;
    if (motion_) context.solver["boundary_work"] = solver_->boundary_work();
  }
  FemCheckpoint checkpoint = make_checkpoint(*model_, state, context);
  if (motion_) {
    const MotionSpec& spec = *case_.fem.motion;
    checkpoint.motion = checkpoint_motion(*motion_, std::string(to_string(spec.base)),
                                          std::string(to_string(spec.input)));
    checkpoint.motion->base_time = state.time;
    checkpoint.motion->base_displacement = mean_base_displacement(state);
  }
  write_checkpoint(file, checkpoint);
  written_.push_back(file);
  last_checkpoint_ = file;
  logger_.info("t = {:.3f} s: wrote {}", state.time, file.string());
}

FemRunSummary FemRun::finish() {
  if (progress_) progress_->finish();
  if (recorders_) recorders_->write();
  FemRunSummary summary;
  summary.steps = steps_;
  summary.elements = model_->element_count();
  summary.end_time = state_.time;
  summary.checkpoints = written_;
  summary.wall_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started_).count();
  // Zone, inversion and KE peak from the whole history (also the rows before a restart).
  bool exited = false;
  for (const auto& row : history_->rows()) {
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
  }
  if (case_.fem.failure_stage) {
    const auto at = [](double t) { return fmt::format("t = {:.3f} s", t); };
    std::string zone;
    if (summary.last_time_in_zone && summary.zone_exit_time) {
      zone = fmt::format("last inside at {}, left at {}", at(*summary.last_time_in_zone),
                         at(*summary.zone_exit_time));
    } else if (summary.last_time_in_zone) {
      zone = fmt::format("inside at every output step, to {}", at(*summary.last_time_in_zone));
    } else if (summary.zone_exit_time) {
      zone = fmt::format("outside from {} on", at(*summary.zone_exit_time));
    } else {
      zone = "no output step";
    }
    logger_.info("recommended transfer zone ((|J_t|/|J_0|)_avg ≥ {}, εq,avg ≤ {}): {}",
                 zone_jacobian_ratio_avg_min, zone_eps_q_avg_max, zone);
    const auto first = [&](const std::optional<double>& t) {
      return t ? fmt::format("first at {}", at(*t)) : std::string("never");
    };
    const std::string inversion =
        summary.first_time_inverted || summary.first_time_jacobian_ratio_negative
            ? fmt::format(
                  "element inverted (det J < 0 at a corner or zero area) {}, (|J_t|/|J_0|)_min < 0 "
                  "{}",
                  first(summary.first_time_inverted),
                  first(summary.first_time_jacobian_ratio_negative))
            : std::string("no element inverted (det J > 0 at every corner at every output step)");
    logger_.info("{}; KE/PE0 peak {:.5f} at {}", inversion, summary.ke_over_pe0_max,
                 at(summary.ke_over_pe0_max_time));
  }
  const std::string text = fmt::format(
      "# fem-solve summary of case {} (times in s; docs/method.md §3)\n"
      "element = {}\n"
      "kinematics = {}\n"
      "end_time = {:.6g}\n"
      "steps = {}\n"
      "elements = {}\n"
      "last_time_in_zone = {}\n"
      "zone_exit_time = {}\n"
      "first_time_jacobian_ratio_negative = {}\n"
      "first_time_inverted = {}\n"
      "ke_over_pe0_max = {:.6g}\n"
      "ke_over_pe0_max_time = {:.6g}\n"
      "wall_s = {:.3f}\n",
      case_.name, to_string(model_->mesh.element_type), to_string(model_->kinematics),
      summary.end_time, state_.step, summary.elements, format_time(summary.last_time_in_zone),
      format_time(summary.zone_exit_time), format_time(summary.first_time_jacobian_ratio_negative),
      format_time(summary.first_time_inverted), summary.ke_over_pe0_max,
      summary.ke_over_pe0_max_time, summary.wall_seconds);
  write_text_atomically(options_.output_dir / "fem_summary.txt", text);
  return summary;
}

}  // namespace

FemRunSummary run_fem(const Case& c, const FemOptions& options, const Logger& logger) {
  FemRun fem_run(c, options, logger);
  return fem_run.execute();
}

}  // namespace slide::fem
