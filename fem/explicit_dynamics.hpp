// Stage 2 of the FE phase: explicit dynamics (docs/method.md §3).
//
// M a = f_ext − f_int with the lumped mass M, gravity f_ext = m_I g and the internal
// (plus hourglass) forces of the elements, integrated by the leapfrog scheme, written
// as a symplectic Euler step (the central-difference method with a velocity stored at
// mid-step):
//   1. forces from the current state:      F_n = m g − f_int(σ_n, Q_n) − β_K K₀ v_{n−1/2}
//      (the last term the optional stiffness-proportional Rayleigh damping, a viscous
//      stress in the element forces; see fem/element_kernels.hpp)
//   2. nodal velocity update:              v_{n+1/2} = constrain(v_{n−1/2} + dt F_n/m)
//      through the shared update of common/physics/nodal_update.hpp (damping, fixed, roller and
//      Coulomb friction nodes exactly as the MPM grid does it); the frictional base is
//      also a contact plane for every other node, so that a toe folding down onto the
//      ground lands on it instead of passing through (small strain runs on past
//      inversion, and without it nodes sank below y = 0 and KE/PE0 exceeded 1)
//   3. positions:                          u_{n+1} = u_n + dt v_{n+1/2}
//   4. strain increment and stress update: Δε = dt sym∇v_{n+1/2}, σ_{n+1} = model(σ_n, Δε)
// A shaken stage (docs/method.md §8, fem/seismic_boundary.hpp) adds to step 2 the static
// reactions, the incident forces and the dashpots of its boundaries, ties the side pairs,
// and applies the constraints to the velocity relative to a moving rigid base.
// A step depends only on the stored state (u, v, σ, state, Q) and dt, so a run restarted
// from a checkpoint continues bit for bit. Small strain evaluates ∇ on the reference
// geometry; updated Lagrangian on x_{n+1}, rotates σ by the Jaumann spin first, and
// refuses a step that would invert an element (the state is then left at t_n).
#pragma once

#include <algorithm>
#include <optional>
#include <span>
#include <vector>

#include "common/physics/constitutive.hpp"
#include "common/physics/nodal_update.hpp"
#include "common/settings/fem_spec.hpp"
#include "fem/fem_model.hpp"
#include "fem/pore_fluid.hpp"
#include "fem/seismic_boundary.hpp"

namespace slide::fem {

/// The damping of the failure stage (docs/method.md §3): the nodal terms of the shared update
/// (mass-proportional Rayleigh α_M, Cundall local α), applied to the nodal force with
/// v_{n−1/2}, and the stiffness-proportional Rayleigh term β_K, a viscous stress in the
/// element forces with the same v_{n−1/2}. Together C = α_M M + β_K K₀.
struct Damping {
  NodalDamping nodal;
  double rayleigh_stiffness = 0.0;  ///< β_K, s
};

/// The damping a case asks for (α_M and β_K already derived from a ratio form).
Damping damping_of(const DampingSpec& spec);

class ExplicitSolver {
 public:
  /// `models` is indexed by material id (the failure stage's constitutive models).
  ExplicitSolver(const FemModel& model, NodalConstraints constraints, double friction_coefficient,
                 Damping damping, std::vector<ConstitutiveModel> models);

  /// The switch from the elastic geostatic state to the failure-stage models
  /// (ConstitutiveModel::start on every Gauss point): Mohr–Coulomb returns stresses
  /// outside its surface to it, multi-yield freezes each point's peak strength and sets
  /// its surfaces. Returns how many points had to be brought onto the surface.
  std::size_t return_to_yield_surface(FemState& state) const;

  /// Courant step at C = 1, dt_c = min_e(l_e/c_p), of the reference (small strain) or
  /// current (updated Lagrangian) geometry, without damping.
  double critical_time_step(const FemState& state);
  /// The same with the skeleton's speeds (ElementConstants::skeleton_wave_speed): the
  /// frequency the stiffness damping acts on; critical_time_step when dry.
  double skeleton_time_step(const FemState& state);

  /// The step the run takes: C·dt_c, lowered by the stiffness damping β_K
  /// (damped_time_step in fem/element_kernels.hpp; equal to C·dt_c when β_K = 0).
  double stable_time_step(const FemState& state, double courant);

  /// One step of length dt. Returns −1, or for updated Lagrangian the first element the
  /// step would invert (det J ≤ 0), in which case `state` is left unchanged.
  Index step(FemState& state, double dt);

  /// The velocity at the state's time, v(t_n) = v_{n−1/2} + (dt/2) F_n/m: a half step of
  /// the same constrained nodal update with the forces of the current state (`dt` the
  /// length of the step that led to it). Energies use it so that kinetic and potential
  /// energy refer to the same instant.
  void synchronised_velocity(const FemState& state, double dt, std::vector<Vec2>& velocity);

  /// Shaking (docs/method.md §8): the boundaries of fem/seismic_boundary.hpp from now on
  /// (none: the static base). The boundary must outlive the solver.
  void set_seismic(const SeismicBoundary* boundary) { seismic_ = boundary; }
  /// The work the boundaries of a shaken stage have done on the body since its start
  /// (J/m): the prescribed base, the dashpots and incident forces, the static reactions.
  /// The energy guard measures the total energy against it.
  double boundary_work() const { return boundary_work_; }
  /// The Darcy term's stable step (pore_fluid_time_step; infinite for a dry model).
  double fluid_time_step() const { return fluid_step_; }
  /// Pore pressures held at the fluid's tension limit so far (node-steps).
  std::size_t pressure_clamps() const { return pressure_clamps_; }
  void set_boundary_work(double work) { boundary_work_ = work; }

  /// The straight line of the frictional base nodes, if they lie on one.
  struct BasePlane {
    NodalConstraint contact;  ///< friction, with the base's outward normal of the body
    Vec2 point;               ///< a point of the base
    /// How far a node at x is above the base (0 on or below it).
    double gap(const Vec2& x) const { return std::max(0.0, -(x - point).dot(contact.normal)); }
  };
  const std::optional<BasePlane>& base_plane() const { return base_plane_; }

 private:
  const ElementGeometry& geometry_for(const FemState& state);
  /// The elements' nodal forces of `state` into kernels_.element_force: internal, hourglass and
  /// damping forces, and the pore pressure's.
  void element_forces(const FemState& state);
  /// The pore pressure's step (advance_pore_pressure), the tied side elements sharing it
  /// in a shaken stage.
  void advance_water(const ElementGeometry& geometry, double dt, FemState& state);
  void update_nodes(FemState& state, double dt);
  Vec2 nodal_force(Index node) const;

  /// The constrained velocity of one node from its trial velocity; the constraints act on
  /// the velocity relative to `frame_velocity` and gaps are measured from
  /// `frame_displacement` (a rigid base's motion; zero for a static base).
  template <bool MovingBase>
  Vec2 constrained_velocity(Index node, const FemState& state, const Vec2& trial, double dt,
                            const Vec2& frame_velocity, const Vec2& frame_displacement) const;
  /// The velocities after a step of length dt from state.velocity, with the element
  /// forces in kernels_.element_force; adds the work of the boundaries to `boundary_work`.
  void nodal_velocities(const FemState& state, double dt, std::vector<Vec2>& velocity,
                        double* boundary_work);

  const FemModel& model_;
  NodalConstraints constraints_;
  std::optional<BasePlane> base_plane_;
  double friction_coefficient_;
  Damping damping_;
  std::vector<ConstitutiveModel> models_;
  bool updated_lagrangian_;
  const SeismicBoundary* seismic_ = nullptr;
  double boundary_work_ = 0.0;
  double fluid_step_ = 0.0;  ///< the Darcy term's stable step (pore_fluid_time_step)
  std::size_t pressure_clamps_ = 0;
  PressureScratch pressure_scratch_;  ///< scratch of the pore-pressure update
  /// Scratch of the nodal update.
  struct NodalScratch {
    std::vector<Vec2> next_velocity, trial;
  };
  NodalScratch scratch_;
  /// What the step's kernels hand on: the elements' nodal forces (n_elements ×
  /// nodes_per_element) to the nodal update, and the Gauss points' multi-yield components
  /// from one step to the next (one per point when a model is multi-yield, else none:
  /// computing them costs as much as the update).
  struct KernelScratch {
    std::vector<Vec2> element_force;
    std::vector<multi_yield::KeptComponents> kept_components;
  };
  KernelScratch kernels_;
  /// Updated Lagrangian: the current geometry, valid for state step `geometry_step`,
  /// and the nodal state saved before a step that might invert an element.
  struct CurrentGeometry {
    ElementGeometry current;
    Index geometry_step = -1;
    std::vector<Vec2> coordinates;
    std::vector<Vec2> saved_displacement, saved_velocity, saved_acceleration;
  };
  CurrentGeometry ul_;
};

}  // namespace slide::fem
