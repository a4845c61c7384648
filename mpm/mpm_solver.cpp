#include "mpm/mpm_solver.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace slide::mpm {

MpmSettings MpmSettings::from(const MpmSpec& spec) {
  MpmSettings s;
  s.grid = GridGeometry::covering(spec.domain_min, spec.domain_max, spec.cell_size);
  s.boundaries = GridBoundaries::from(spec.boundaries, spec.friction_coefficient);
  s.shape_function = spec.shape_function;
  s.update_scheme = spec.update_scheme;
  s.velocity_transfer = spec.velocity_transfer;
  s.pic_fraction = spec.pic_fraction;
  s.volumetric_smoothing = spec.volumetric_smoothing;
  s.damping.local = spec.local_damping;
  s.particle_exit = spec.particle_exit;
  if (spec.undrained_pore_pressure) s.pore_fluid_bulk_modulus = spec.water_bulk_modulus;
  if (spec.reservoir_level) {
    s.reservoir = {*spec.reservoir_level, spec.water_density * -s.gravity.y(), spec.reservoir_x_min,
                   spec.reservoir_x_max};
  }
  return s;
}

MpmSolver::MpmSolver(MpmSettings settings, MaterialTable materials, Particles particles,
                     SolverClock clock)
    : settings_(std::move(settings)),
      materials_(std::move(materials)),
      particles_(std::move(particles)),
      clock_(clock) {
  // The surfaces the MPM models need: a particle file of the same models brings them,
  // anything else (pure MPM, other FE models) starts without (the switch sets them).
  const std::size_t surfaces = surfaces_needed(materials_, Phase::mpm);
  if (particles_.surface_stress.per_point != surfaces) {
    particles_.surface_stress = SurfaceStresses{surfaces, {}};
    particles_.surface_stress.resize(particles_.count());
  }
  // FLIP/PIC carries no affine state: an APIC checkpoint's B_p are dropped (the restart
  // warns of the changed transfer); APIC starts particles without one at B_p = 0.
  if (settings_.velocity_transfer != VelocityTransfer::apic) particles_.affine_velocity.clear();
  size_affine_velocity();
  particles_.check_consistent_sizes();
  // The arrays are permuted in place from now on: drop the slack a generator may have
  // left (push_back growth), which would otherwise stay for the whole run.
  particles_.shrink_to_fit();
  use_elastic_models(false);
  grid_state_.resize(settings_.grid);
  double smallest_mass = std::numeric_limits<double>::infinity();
  for (double m : particles_.mass) smallest_mass = std::min(smallest_mass, m);
  // Nodes lighter than this are empty: 1e-14 of a particle is far below any weight a
  // particle gives a node it actually moves, and keeps p/m and F/m finite.
  mass_floor_ = particles_.count() > 0 ? 1e-14 * smallest_mass : 0.0;
}

void MpmSolver::size_affine_velocity() {
  // B_p = 0: the particle hands its velocity alone to the grid on its first step (a
  // particle file has no affine state: fem2mpm writes none).
  if (settings_.velocity_transfer == VelocityTransfer::apic &&
      particles_.affine_velocity.size() != particles_.count()) {
    particles_.affine_velocity.assign(particles_.count(), Vec4::Zero());
  }
}

void MpmSolver::use_elastic_models(bool elastic) {
  // Each material's MPM model, then its liquefied state (kernels.hpp, particle_model):
  // the residual strength, or the same model for a material without one.
  // Undrained pore water lives in the saturated materials' own models; a liquefied state
  // is a total-stress model whose undrained ν holds the water's stiffness already.
  const double fluid = settings_.pore_fluid_bulk_modulus;
  auto own = [&](const Material& m) {
    ConstitutiveModel model = ConstitutiveModel::from(m, Phase::mpm);
    if (fluid > 0.0 && m.saturable()) model.set_pore_fluid_stiffness(fluid / m.porosity);
    return model;
  };
  models_.clear();
  for (const Material& m : materials_) {
    models_.push_back(elastic ? ConstitutiveModel::elastic(m) : own(m));
  }
  for (const Material& m : materials_) {
    models_.push_back(elastic                    ? ConstitutiveModel::elastic(m)
                      : has_residual_strength(m) ? ConstitutiveModel::liquefied(m)
                                                 : own(m));
  }
}

MpmSolver::Settling MpmSolver::settle_under_gravity(double duration, double local_damping,
                                                    double dt) {
  const NodalDamping kept = settings_.damping;
  settings_.damping.local = local_damping;
  use_elastic_models(true);
  Settling settling;
  while (clock_.time < duration - 1e-12) {
    step(std::min(dt, duration - clock_.time));
    ++settling.steps;
  }
  settling.kinetic_energy = energies().kinetic;
  settings_.damping = kept;
  use_elastic_models(false);
  Particles& q = particles_;
  located_ = false;
  for (std::size_t k = 0; k < q.count(); ++k) {
    q.velocity[k].setZero();
    if (!q.affine_velocity.empty()) q.affine_velocity[k].setZero();
    q.displacement[k].setZero();
    q.strain[k].setZero();
    q.eps_q[k] = 0.0;
    q.state[k] = MaterialState{};
  }
  clock_.time = 0.0;
  clock_.step = 0;
  clock_.previous_dt = 0.0;
  return settling;
}

std::size_t MpmSolver::return_to_yield_surface() {
  std::size_t returned = 0;
  located_ = false;
  for (std::size_t p = 0; p < active_count(); ++p) {
    const auto& model = models_[particle_model(particles_, p, materials_.size())];
    const bool returned_here = on_model_stress(model, particles_, p, [&](Vec4& stress) {
      return model.start(stress, particles_.state[p], particles_.surface_stress.of(p));
    });
    if (returned_here) ++returned;
  }
  return returned;
}

void MpmSolver::locate() {
  // The last step's final pass located the particles already, unless something moved
  // them since (setup, a sort).
  LocateResult located = located_ ? std::move(pending_)
                                  : locate_particles(particles_, active_count(), settings_.grid,
                                                     settings_.shape_function, blocks_);
  located_ = false;
  if (located.non_finite >= 0) {
    const auto p = static_cast<std::size_t>(located.non_finite);
    throw InstabilityError(
        "instability: particle {} (id {}) has a non-finite position at t = {:.6g} s (step {})", p,
        particles_.id[p], clock_.time, clock_.step);
  }
  if (located.outside.empty()) return;
  // Particles that left the grid: frozen behind the active ones, or removed. The order of
  // the others is kept, so the run stays deterministic.
  exited_this_step_ += located.outside.size();
  const std::size_t active =
      retire_particles(particles_, active_count(), located.outside, settings_.particle_exit);
  clock_.frozen = particles_.count() - active;
  blocks_.partition(active);
  located = locate_particles(particles_, active, settings_.grid, settings_.shape_function, blocks_);
}

void MpmSolver::sort() {
  sort_particles_by_cell(particles_, active_count(), settings_.grid);
  clock_.steps_since_sort = 0;
  clock_.sorted_once = true;
  locate_particles(particles_, active_count(), settings_.grid, settings_.shape_function, blocks_);
}

StepReport MpmSolver::step(double dt) {
  if (!(dt > 0.0) || !std::isfinite(dt)) throw Error("mpm: time step {} is not admissible", dt);
  const StepLengths lengths{dt, 0.5 * (clock_.previous_dt + dt)};
  const MpmSettings& s = settings_;
  exited_this_step_ = 0;
  size_affine_velocity();  // the settings may have switched to APIC since the start
  if (base_.motion) follow_base(dt);

  const bool sorting = !clock_.sorted_once || clock_.steps_since_sort >= s.sort_interval;
  if (subdomain_) exchange_particles(sorting);
  locate();
  if (sorting) sort();

  particles_to_grid(particles_, s.grid, s.shape_function, s.velocity_transfer, s.gravity, blocks_,
                    grid_state_, s.reservoir);
  sum_node_windows(s.grid, blocks_, grid_state_);
  if (subdomain_) {
    subdomain_->check_reach(s.grid, grid_state_.active_begin, grid_state_.active_end);
    subdomain_->sum_shared(s.grid, grid_state_.active_begin, grid_state_.active_end,
                           grid_state_.sums);
  }
  double power =
      update_nodes(s.grid, s.boundaries, s.damping, lengths.dt_velocity, mass_floor_, grid_state_);
  if (subdomain_ && s.boundaries.moving) power = subdomain_->ranks().sum(power);
  clock_.boundary_work += power * dt;
  if (s.update_scheme == UpdateScheme::musl) {
    remap_momenta(particles_, s.grid, s.shape_function, s.velocity_transfer, lengths,
                  s.pic_fraction, blocks_, grid_state_);
    if (subdomain_) {
      subdomain_->sum_shared(s.grid, grid_state_.active_begin, grid_state_.active_end,
                             grid_state_.remapped_velocity);
    }
    finish_remapped_velocities(s.grid, s.boundaries, mass_floor_, grid_state_);
  }
  pending_ = grid_to_particles(particles_, s.grid, s.shape_function, s.update_scheme,
                               s.velocity_transfer, lengths, s.pic_fraction, s.volumetric_smoothing,
                               models_, blocks_, grid_state_);
  located_ = true;

  clock_.time += dt;
  clock_.step += 1;
  clock_.previous_dt = dt;
  clock_.steps_since_sort += 1;
  last_kinetic_energy_ = 0.0;
  for (double e : blocks_.kinetic_energy) last_kinetic_energy_ += e;
  if (subdomain_) {
    std::array<double, 2> totals{last_kinetic_energy_, static_cast<double>(exited_this_step_)};
    subdomain_->ranks().sum(totals);
    last_kinetic_energy_ = totals[0];
    exited_this_step_ = static_cast<std::size_t>(totals[1]);
  }
  return {exited_this_step_};
}

void MpmSolver::distribute(const Ranks& ranks, const Decomposition& decomposition) {
  if (!ranks.distributed()) return;
  const GridGeometry& grid = settings_.grid;
  SlabCuts cuts;
  if (decomposition.cuts) {
    cuts = *decomposition.cuts;
  } else {
    // The particles per cell column of the whole body: the sum of the ranks' parts.
    std::vector<std::int64_t> histogram = particles_per_column(particles_, active_count(), grid);
    ranks.sum(std::span<std::int64_t>(histogram));
    cuts = SlabCuts::balanced(histogram, ranks.size());
  }
  cuts.check(grid.cells_x);
  subdomain_.emplace(ranks, std::move(cuts));
  subdomain_->rebalance_share = decomposition.rebalance_share;
  const std::size_t active =
      subdomain_->scatter(particles_, clock_.frozen, grid, packed_layout(),
                          decomposition.held ? &*decomposition.held : nullptr);
  clock_.frozen = particles_.count() - active;
  located_ = false;
  set_own_columns();
}

PackedLayout MpmSolver::packed_layout() const {
  // The saturated transfer's fields are the run's when any rank has them (a rank with
  // no particle holds them empty).
  double pore_water = particles_.liquefied.empty() ? 0.0 : 1.0;
  if (subdomain_) pore_water = subdomain_->ranks().max(pore_water);
  return {particles_.surface_stress.per_point,
          settings_.velocity_transfer == VelocityTransfer::apic, pore_water > 0.0};
}

void MpmSolver::set_own_columns() {
  const auto [begin, end] = subdomain_->own_node_columns(settings_.grid);
  grid_state_.own_begin = begin;
  grid_state_.own_end = end;
}

void MpmSolver::exchange_particles(bool sorting) {
  bool changed = false;
  const PackedLayout layout = packed_layout();
  std::size_t active =
      subdomain_->migrate(particles_, active_count(), settings_.grid, layout, changed);
  if (sorting && subdomain_->rebalance(particles_, active, settings_.grid, layout)) {
    changed = true;
    set_own_columns();
  }
  if (!changed) return;
  clock_.frozen = particles_.count() - active;
  located_ = false;
}

void MpmSolver::set_base_motion(GroundMotion motion, const CheckpointMotion& record) {
  base_.motion = std::move(motion);
  base_.record = record;
  settings_.boundaries.moving = true;
  base_.resting_origin = settings_.grid.origin;
  settings_.grid.origin = grid_origin_at(clock_.time);
  located_ = false;
}

Vec2 MpmSolver::grid_origin_at(double time) const {
  return base_.motion ? base_.resting_origin + base_position(base_.record, *base_.motion, time)
                      : settings_.grid.origin;
}

/// The grid translates with the base: at the step's start it is where the base is, and
/// over the step its edges move at the base's velocity (the constraints' frame).
void MpmSolver::follow_base(double dt) {
  const Vec2 origin = grid_origin_at(clock_.time);
  if (origin != settings_.grid.origin) {
    settings_.grid.origin = origin;
    located_ = false;  // the last pass located the particles on the grid where it was
  }
  settings_.boundaries.frame_velocity = base_.motion->step_velocity(clock_.time, dt);
}

Energies MpmSolver::energies() const {
  Energies e;
  for (std::size_t p = 0; p < particles_.count(); ++p) {
    const double m = particles_.mass[p];
    e.kinetic += 0.5 * m * particles_.velocity[p].squaredNorm();
    e.potential -= m * settings_.gravity.dot(particles_.coordinates[p]);
    const auto& material = materials_[static_cast<std::size_t>(particles_.material_id[p])];
    e.elastic += particles_.volume[p] * elastic_energy_density(material, particles_.stress[p]);
  }
  if (subdomain_) {
    std::array<double, 3> totals{e.kinetic, e.potential, e.elastic};
    subdomain_->ranks().sum(totals);
    e = {totals[0], totals[1], totals[2]};
  }
  return e;
}

MpmSolver::Speeds MpmSolver::max_speeds(double node_mass_share) const {
  Speeds s;
  double smallest_mass = std::numeric_limits<double>::infinity();
  for (std::size_t p = 0; p < particles_.count(); ++p) {
    smallest_mass = std::min(smallest_mass, particles_.mass[p]);
    const double speed = particles_.velocity[p].norm();
    if (!(speed <= s.particle)) {  // also catches NaN
      s.particle = speed;
      s.particle_index = p;
    }
  }
  const double threshold = node_mass_share * smallest_mass;
  const auto rows = static_cast<std::size_t>(settings_.grid.node_rows());
  for (auto column = static_cast<std::size_t>(grid_state_.active_begin);
       column < static_cast<std::size_t>(grid_state_.active_end); ++column) {
    for (std::size_t row = 0; row < rows; ++row) {
      const std::size_t k = column * rows + row;
      if (!(grid_state_.sums[k].mass >= threshold)) continue;
      const NodeMotion& m = grid_state_.motion[k];
      const double speed = std::hypot(m.velocity_x, m.velocity_y);
      if (!(speed <= s.node)) {
        s.node = speed;
        s.node_position = settings_.grid.node_position(k);
      }
    }
  }
  return s;
}

double MpmSolver::grid_mass() const {
  double total = 0.0;
  const auto rows = static_cast<std::size_t>(settings_.grid.node_rows());
  for (auto k = static_cast<std::size_t>(grid_state_.active_begin) * rows;
       k < static_cast<std::size_t>(grid_state_.active_end) * rows; ++k) {
    total += grid_state_.sums[k].mass;
  }
  return total;
}

void MpmSolver::check_volume(std::size_t p, double wave_speed_squared) const {
  if (!std::isfinite(wave_speed_squared) || !(wave_speed_squared > 0.0)) {
    // A volume gone to zero, below it, to infinity or NaN: the run has blown up (the
    // linear shape's cell crossing in a stiff sliding block did so); name the particle.
    throw InstabilityError(
        "instability at t = {:.6g} s (step {}): particle {} (id {}) at ({:.3f}, {:.3f}) m has "
        "volume {} m^3/m, so no Courant step exists",
        clock_.time, clock_.step, p, particles_.id[p], particles_.coordinates[p].x(),
        particles_.coordinates[p].y(), particles_.volume[p]);
  }
  // ρ_material / ρ_p = V_p ρ / m_p: a soil dilates by tens of per cent, an isolated
  // particle at the apex of its yield surface by tens of times (mpm/README.md, "Time
  // step": 35 in a run that then came to rest). Ten thousand times is a blow-up, whose
  // step would crawl toward zero for minutes before the volume overflows.
  const double density = materials_[static_cast<std::size_t>(particles_.material_id[p])].density;
  if (particles_.volume[p] * density > max_expansion * particles_.mass[p]) {
    throw InstabilityError(
        "instability at t = {:.6g} s (step {}): particle {} (id {}) at ({:.3f}, {:.3f}) m has "
        "expanded to {:.3g} times its material's volume at rest (more than {:g}), so the "
        "Courant step would fall below 1/{:g} of the material's",
        clock_.time, clock_.step, p, particles_.id[p], particles_.coordinates[p].x(),
        particles_.coordinates[p].y(), particles_.volume[p] * density / particles_.mass[p],
        max_expansion, std::sqrt(max_expansion));
  }
}

double MpmSolver::courant_time_step(double courant) const {
  // c_p² = M V_p / m_p: the P-wave speed at the particle's current density. A particle
  // that has expanded (a lone particle at the front, at the Mohr–Coulomb apex) is a faster
  // oscillator than the material at rest: slope-frictional's t_T = 4 s run blew up at
  // 20.9 s with one particle at 35 times its volume while the step was still that of the
  // initial density (mpm/README.md, "Time step").
  // M = λ + 2G of each model (liquefied states included: kernels.hpp, particle_model).
  // The pore water's K_f/n adds to M where the particle holds water (holds_water).
  std::vector<double> modulus(models_.size()), water(models_.size());
  for (std::size_t m = 0; m < models_.size(); ++m) {
    modulus[m] = models_[m].lame_lambda() + 2.0 * models_[m].shear_modulus();
    water[m] = models_[m].pore_fluid_stiffness();
  }
  double fastest_squared = 0.0;
  for (std::size_t p = 0; p < active_count(); ++p) {
    const std::size_t m = particle_model(particles_, p, materials_.size());
    const double stiffness =
        modulus[m] + (water[m] > 0.0 && holds_water(particles_, p) ? water[m] : 0.0);
    const double c2 = stiffness * particles_.volume[p] / particles_.mass[p];
    check_volume(p, c2);
    fastest_squared = std::max(fastest_squared, c2);
  }
  if (subdomain_) {
    // The body's fastest particle sets every rank's step; a rank without active
    // particles has none to offer.
    fastest_squared = subdomain_->ranks().max(fastest_squared);
    if (fastest_squared == 0.0) {
      for (const Material& m : materials_)
        fastest_squared = std::max(fastest_squared, std::pow(m.p_wave_speed(), 2));
    }
  } else if (active_count() == 0) {
    for (auto id : particles_.material_id)
      fastest_squared = std::max(
          fastest_squared, std::pow(materials_[static_cast<std::size_t>(id)].p_wave_speed(), 2));
  }
  if (!(fastest_squared > 0.0) || !std::isfinite(fastest_squared))
    throw Error("mpm: no particle with a finite wave speed for the Courant step");
  return courant * settings_.grid.cell_size / std::sqrt(fastest_squared);
}

MpmSolver::Memory MpmSolver::memory() const {
  Memory m;
  const Particles& p = particles_;
  m.particle_arrays = p.bytes();
  // The sort (in place): the permutation and its cycles (RowCycles), at most 8 B per
  // particle, and the bucket table.
  m.sort_peak = 2 * p.count() * sizeof(std::uint32_t) +
                (settings_.grid.cell_count() + 2) * sizeof(std::uint32_t);
  m.grid = grid_state_.bytes() + blocks_.bytes();
  return m;
}

void validate_particles(const Particles& particles, const MpmSettings& settings,
                        std::size_t material_count, const std::string& source, std::size_t frozen) {
  particles.check_consistent_sizes();
  if (particles.count() == 0) throw Error("{}: no particles", source);
  const std::size_t active = particles.count() - std::min(frozen, particles.count());
  const GridGeometry& g = settings.grid;
  const Vec2 top = g.upper_corner();
  for (std::size_t p = 0; p < particles.count(); ++p) {
    const auto name = [&] {
      return fmt::format("{}: particle {} (id {})", source, p, particles.id[p]);
    };
    const Vec2& x = particles.coordinates[p];
    if (!x.allFinite()) throw Error("{}: coordinates are not finite", name());
    if (!particles.velocity[p].allFinite()) {
      throw Error("{}: velocity ({}, {}) is not finite", name(), particles.velocity[p].x(),
                  particles.velocity[p].y());
    }
    if (!particles.displacement[p].allFinite())
      throw Error("{}: displacement is not finite", name());
    if (!particles.stress[p].allFinite()) throw Error("{}: stress is not finite", name());
    if (!particles.strain[p].allFinite()) throw Error("{}: strain is not finite", name());
    if (!particles.affine_velocity.empty() && !particles.affine_velocity[p].allFinite())
      throw Error("{}: affine velocity is not finite", name());
    if (!(particles.mass[p] > 0.0) || !std::isfinite(particles.mass[p])) {
      throw Error("{}: mass {} kg/m is not admissible (expected > 0)", name(), particles.mass[p]);
    }
    if (!(particles.volume[p] > 0.0) || !std::isfinite(particles.volume[p])) {
      throw Error("{}: volume {} m³/m is not admissible (expected > 0)", name(),
                  particles.volume[p]);
    }
    const Vec2& size = particles.size[p];
    if (settings.shape_function == ShapeFunction::gimp &&
        (!(size.x() > 0.0) || !(size.y() > 0.0) || !size.allFinite())) {
      throw Error("{}: GIMP size ({}, {}) m is not admissible (expected > 0)", name(), size.x(),
                  size.y());
    }
    const auto material = particles.material_id[p];
    if (material < 0 || static_cast<std::size_t>(material) >= material_count) {
      throw Error("{}: unknown material id {} (the case defines {} material{})", name(), material,
                  material_count, material_count == 1 ? "" : "s");
    }
    if (p < active && !g.contains(x)) {
      throw Error(
          "{}: position ({}, {}) m is outside the grid [{}, {}] × [{}, {}] m (half a cell of "
          "margin allowed)",
          name(), x.x(), x.y(), g.origin.x(), top.x(), g.origin.y(), top.y());
    }
  }
}

}  // namespace slide::mpm
