#include "fem/explicit_dynamics.hpp"

#include <algorithm>

#include "fem/element_kernels.hpp"
#include "fem/pore_fluid.hpp"

namespace slide::fem {

namespace {

// How far a node of the frictional base has lifted off it (0 for nodes on no frictional
// boundary): base nodes start on the base, so the gap follows from the displacement.
double base_gap(std::span<const NodalConstraint> constraints, const Vec2& displacement) {
  double gap = 0.0;
  for (const auto& c : constraints) {
    if (c.condition == BoundaryCondition::friction) gap = contact_gap(c, displacement);
  }
  return gap;
}

bool on_frictional_base(std::span<const NodalConstraint> constraints) {
  return std::ranges::any_of(constraints, [](const NodalConstraint& c) {
    return c.condition == BoundaryCondition::friction;
  });
}

// The line through the frictional nodes when they are collinear with one common normal
// (every case's base y = 0); none otherwise (a curved or absent frictional boundary is
// then only a constraint on its own nodes).
std::optional<ExplicitSolver::BasePlane> find_base_plane(const Mesh& mesh,
                                                         const NodalConstraints& constraints) {
  std::optional<ExplicitSolver::BasePlane> plane;
  double extent = 0.0;
  for (Index node = 0; node + 1 < static_cast<Index>(constraints.offsets.size()); ++node) {
    for (const auto& c : constraints.of(node)) {
      if (c.condition != BoundaryCondition::friction) continue;
      const Vec2& x = mesh.nodes[static_cast<std::size_t>(node)];
      if (!plane) {
        plane = ExplicitSolver::BasePlane{c, x};
        continue;
      }
      if ((c.normal - plane->contact.normal).norm() > 1e-12) return std::nullopt;
      extent = std::max(extent, (x - plane->point).norm());
      if (std::abs((x - plane->point).dot(c.normal)) > 1e-9 * std::max(extent, 1.0)) {
        return std::nullopt;
      }
    }
  }
  return plane;
}

}  // namespace

Damping damping_of(const DampingSpec& spec) {
  return {NodalDamping{spec.rayleigh_mass, spec.local}, spec.rayleigh_stiffness};
}

ExplicitSolver::ExplicitSolver(const FemModel& model, NodalConstraints constraints,
                               double friction_coefficient, Damping damping,
                               std::vector<ConstitutiveModel> models)
    : model_(model),
      constraints_(std::move(constraints)),
      base_plane_(find_base_plane(model.mesh, constraints_)),
      friction_coefficient_(friction_coefficient),
      damping_(damping),
      models_(std::move(models)),
      updated_lagrangian_(model.kinematics == Kinematics::updated_lagrangian),
      fluid_step_(pore_fluid_time_step(model)) {
  kernels_.element_force.resize(
      static_cast<std::size_t>(model.element_count() * model.nodes_per_element));
  const bool multi_yield = std::ranges::any_of(models_, [](const ConstitutiveModel& m) {
    return m.model() == MaterialModel::pressure_independent_multi_yield;
  });
  if (multi_yield) kernels_.kept_components.resize(static_cast<std::size_t>(model.gauss_count()));
}

std::size_t ExplicitSolver::return_to_yield_surface(FemState& state) const {
  std::size_t returned = 0;
  const auto n_gauss = static_cast<std::size_t>(model_.gauss_per_element());
  for (std::size_t gp = 0; gp < state.stress.size(); ++gp) {
    const auto element = gp / n_gauss;
    const ConstitutiveModel& m =
        models_[static_cast<std::size_t>(model_.mesh.material_id[element])];
    const bool moved =
        m.start(state.stress[gp], state.material_state[gp], state.surface_stress.of(gp));
    state.yielded[gp] = moved ? 1 : 0;
    returned += moved ? 1 : 0;
  }
  return returned;
}

const ElementGeometry& ExplicitSolver::geometry_for(const FemState& state) {
  if (!updated_lagrangian_) return model_.reference;
  if (ul_.geometry_step != state.step) {
    update_coordinates(model_, state, ul_.coordinates);
    compute_geometry(model_, ul_.coordinates, ul_.current);
    ul_.geometry_step = state.step;
  }
  return ul_.current;
}

double ExplicitSolver::critical_time_step(const FemState& state) {
  if (!updated_lagrangian_) return courant_time_step(model_, model_.mesh.nodes, 1.0);
  update_coordinates(model_, state, ul_.coordinates);
  return courant_time_step(model_, ul_.coordinates, 1.0);
}

double ExplicitSolver::skeleton_time_step(const FemState& state) {
  const auto& speed = model_.elements.skeleton_wave_speed;
  if (!updated_lagrangian_) return courant_time_step(model_, model_.mesh.nodes, 1.0, speed);
  update_coordinates(model_, state, ul_.coordinates);
  return courant_time_step(model_, ul_.coordinates, 1.0, speed);
}

double ExplicitSolver::stable_time_step(const FemState& state, double courant) {
  const double critical = critical_time_step(state);
  // Only a saturated model's skeleton is slower than the mixture, and only β_K asks.
  const bool skeleton = model_.fluid.active() && damping_.rayleigh_stiffness > 0.0;
  return std::min(damped_time_step(critical, courant, damping_.rayleigh_stiffness,
                                   skeleton ? skeleton_time_step(state) : critical),
                  fluid_step_);
}

Vec2 ExplicitSolver::nodal_force(Index node) const {
  const auto n = static_cast<std::size_t>(node);
  Vec2 force = model_.lumped.external_force[n];
  const auto begin = static_cast<std::size_t>(model_.adjacency.offsets[n]);
  const auto end = static_cast<std::size_t>(model_.adjacency.offsets[n + 1]);
  for (std::size_t i = begin; i < end; ++i) {
    force += kernels_.element_force[static_cast<std::size_t>(model_.adjacency.slots[i])];
  }
  return force;
}

// Always inline: called out of line, the node loops kept their running values in memory
// around the call (37 of Mohr–Coulomb's 715 instructions per element-step on column-short).
template <bool MovingBase>
[[gnu::always_inline]] inline Vec2 ExplicitSolver::constrained_velocity(
    Index node, const FemState& state, const Vec2& trial, double dt, const Vec2& frame_velocity,
    const Vec2& frame_displacement) const {
  // The static base skips the frame's arithmetic (a tenth of the nodal update's work).
  const auto relative = [&](const Vec2& v) { return MovingBase ? Vec2(v - frame_velocity) : v; };
  const auto absolute = [&](const Vec2& v) { return MovingBase ? Vec2(v + frame_velocity) : v; };
  const auto n = static_cast<std::size_t>(node);
  const auto constraints = constraints_.of(node);
  if (on_frictional_base(constraints)) {
    const Vec2 u =
        MovingBase ? Vec2(state.displacement[n] - frame_displacement) : state.displacement[n];
    return absolute(apply_constraints(constraints, friction_coefficient_, relative(trial),
                                      {base_gap(constraints, u), dt}));
  }
  const Vec2 v =
      constraints.empty()
          ? trial
          : absolute(apply_constraints(constraints, friction_coefficient_, relative(trial)));
  if (!base_plane_) return v;
  Vec2 x = model_.mesh.nodes[n] + state.displacement[n];
  if (MovingBase) x -= frame_displacement;
  return absolute(apply_constraint(base_plane_->contact, friction_coefficient_, relative(v),
                                   {base_plane_->gap(x), dt}));
}

void ExplicitSolver::nodal_velocities(const FemState& state, double dt, std::vector<Vec2>& velocity,
                                      double* boundary_work) {
  const auto n_nodes = static_cast<std::size_t>(model_.node_count());
  velocity.resize(n_nodes);
  if (seismic_ == nullptr) {
    for (std::size_t n = 0; n < n_nodes; ++n) {
      const auto node = static_cast<Index>(n);
      const Vec2 trial = damped_trial_velocity(model_.lumped.mass[n], state.velocity[n],
                                               nodal_force(node), dt, damping_.nodal);
      velocity[n] = constrained_velocity<false>(node, state, trial, dt, Vec2::Zero(), Vec2::Zero());
    }
    return;
  }
  const SeismicBoundary& b = *seismic_;
  const Vec2 incident_velocity = b.motion->step_velocity(state.time, dt);
  const Vec2 frame_velocity = b.frame_velocity(state.time, dt);
  const Vec2 frame_displacement = b.frame_displacement(state.time);
  const Vec2 dashpot_reference = b.dashpots_in_base_frame ? frame_velocity : Vec2::Zero();
  scratch_.trial.resize(n_nodes);
  for (std::size_t n = 0; n < n_nodes; ++n) {
    const double m = model_.lumped.mass[n];
    const Vec2 force = nodal_force(static_cast<Index>(n)) + b.static_force[n] +
                       b.incident[n].cwiseProduct(incident_velocity);
    Vec2 trial = damped_trial_velocity(m, state.velocity[n], force, dt, damping_.nodal);
    for (int i = 0; i < 2; ++i) {
      // m (v⁺ − v⁻)/dt = F − c (v⁺ + v⁻)/2, relative to the dashpot's reference.
      const double c = b.dashpot[n][i];
      if (c == 0.0) continue;
      const double r = dashpot_reference[i];
      trial[i] =
          r + (m * (trial[i] - r) - 0.5 * c * dt * (state.velocity[n][i] - r)) / (m + 0.5 * c * dt);
    }
    scratch_.trial[n] = trial;
  }
  for (const auto& [i, j] : b.tied) {
    const auto a = static_cast<std::size_t>(i);
    const auto c = static_cast<std::size_t>(j);
    const double ma = model_.lumped.mass[a];
    const double mc = model_.lumped.mass[c];
    const Vec2 shared = (ma * scratch_.trial[a] + mc * scratch_.trial[c]) / (ma + mc);
    scratch_.trial[a].x() = scratch_.trial[c].x() = shared.x();
    if (b.tie_vertical) scratch_.trial[a].y() = scratch_.trial[c].y() = shared.y();
  }
  double work = 0.0;
  for (std::size_t n = 0; n < n_nodes; ++n) {
    const auto node = static_cast<Index>(n);
    velocity[n] = constrained_velocity<true>(node, state, scratch_.trial[n], dt, frame_velocity,
                                             frame_displacement);
    if (boundary_work == nullptr) continue;
    // The boundaries' force over the step, m (v − v*_free)/dt, times the step's motion.
    const double m = model_.lumped.mass[n];
    const Vec2 free =
        damped_trial_velocity(m, state.velocity[n], nodal_force(node), dt, damping_.nodal);
    work += m * (velocity[n] - free).dot(velocity[n]);
  }
  if (boundary_work != nullptr) *boundary_work += work;
}

void ExplicitSolver::update_nodes(FemState& state, double dt) {
  const auto n_nodes = static_cast<std::size_t>(model_.node_count());
  if (seismic_ == nullptr) {
    // A static base: one pass, no scratch (2.7 % of the step's instructions on
    // column-short when it went through nodal_velocities).
    for (std::size_t n = 0; n < n_nodes; ++n) {
      const auto node = static_cast<Index>(n);
      const Vec2 previous = state.velocity[n];
      const Vec2 trial = damped_trial_velocity(model_.lumped.mass[n], previous, nodal_force(node),
                                               dt, damping_.nodal);
      const Vec2 velocity =
          constrained_velocity<false>(node, state, trial, dt, Vec2::Zero(), Vec2::Zero());
      state.acceleration[n] = (velocity - previous) / dt;
      state.velocity[n] = velocity;
      state.displacement[n] += dt * velocity;
    }
    return;
  }
  nodal_velocities(state, dt, scratch_.next_velocity, &boundary_work_);
  for (std::size_t n = 0; n < n_nodes; ++n) {
    const Vec2& velocity = scratch_.next_velocity[n];
    state.acceleration[n] = (velocity - state.velocity[n]) / dt;
    state.velocity[n] = velocity;
    state.displacement[n] += dt * velocity;
  }
}

void ExplicitSolver::element_forces(const FemState& state) {
  const ElementGeometry& geometry = geometry_for(state);
  compute_element_forces(model_, geometry, state, kernels_.element_force,
                         damping_.rayleigh_stiffness);
  add_pore_pressure_forces(model_, geometry, state.element_pore_pressure, kernels_.element_force);
}

void ExplicitSolver::advance_water(const ElementGeometry& geometry, double dt, FemState& state) {
  std::span<const std::pair<Index, Index>> tied;
  if (seismic_ != nullptr) tied = seismic_->tied_elements;
  pressure_clamps_ +=
      advance_pore_pressure(model_, geometry, dt, tied, state, pressure_scratch_).clamped;
}

Index ExplicitSolver::step(FemState& state, double dt) {
  // r_u,max is the largest pore-pressure ratio of the shaking and after it: the rest
  // before the motion (a PM4Sand soil settling into its switch) does not count.
  if (seismic_ != nullptr && seismic_->motion != nullptr) {
    const double start = seismic_->motion->start_time();
    if (state.time <= start && start < state.time + dt) {
      std::ranges::fill(state.max_pore_pressure_ratio, 0.0);
    }
  }
  element_forces(state);
  if (!updated_lagrangian_) {
    update_nodes(state, dt);
    update_stresses(model_, model_.reference, models_, dt, false, state, kernels_.kept_components);
    advance_water(model_.reference, dt, state);
  } else {
    ul_.saved_displacement = state.displacement;
    ul_.saved_velocity = state.velocity;
    ul_.saved_acceleration = state.acceleration;
    const double saved_work = boundary_work_;
    update_nodes(state, dt);
    update_coordinates(model_, state, ul_.coordinates);
    const Index inverted = compute_geometry(model_, ul_.coordinates, ul_.current);
    if (inverted >= 0) {
      state.displacement.swap(ul_.saved_displacement);
      state.velocity.swap(ul_.saved_velocity);
      state.acceleration.swap(ul_.saved_acceleration);
      boundary_work_ = saved_work;
      ul_.geometry_step = -1;
      return inverted;
    }
    update_stresses(model_, ul_.current, models_, dt, true, state, kernels_.kept_components);
    advance_water(ul_.current, dt, state);
    ul_.geometry_step = state.step + 1;
  }
  state.time += dt;
  state.step += 1;
  return -1;
}

void ExplicitSolver::synchronised_velocity(const FemState& state, double dt,
                                           std::vector<Vec2>& velocity) {
  if (!(dt > 0.0)) {
    velocity = state.velocity;
    return;
  }
  element_forces(state);
  nodal_velocities(state, 0.5 * dt, velocity, nullptr);
}

}  // namespace slide::fem
