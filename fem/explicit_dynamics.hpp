// Stage 2 of the FE phase: explicit dynamics (METHOD.md §3).
//
// M a = f_ext − f_int with the lumped mass M, gravity f_ext = m_I g and the internal
// (plus hourglass) forces of the elements, integrated by the leapfrog scheme, written
// as a symplectic Euler step (the central-difference method with a velocity stored at
// mid-step):
//   1. forces from the current state:      F_n = m g − f_int(σ_n, Q_n)
//   2. nodal velocity update:              v_{n+1/2} = constrain(v_{n−1/2} + dt F_n/m)
//      through the shared update of common/nodal_update.hpp (damping, fixed, roller and
//      Coulomb friction nodes exactly as the MPM grid does it)
//   3. positions:                          u_{n+1} = u_n + dt v_{n+1/2}
//   4. strain increment and stress update: Δε = dt sym∇v_{n+1/2}, σ_{n+1} = model(σ_n, Δε)
// A step depends only on the stored state (u, v, σ, state, Q) and dt, so a run restarted
// from a checkpoint continues bit for bit. Small strain evaluates ∇ on the reference
// geometry; updated Lagrangian on x_{n+1}, rotates σ by the Jaumann spin first, and
// refuses a step that would invert an element (the state is then left at t_n).
#pragma once

#include <span>
#include <vector>

#include "common/constitutive.hpp"
#include "common/nodal_update.hpp"
#include "fem/fem_model.hpp"

namespace slide::fem {

class ExplicitSolver {
 public:
  /// `models` is indexed by material id (the failure stage's constitutive models).
  ExplicitSolver(const FemModel& model, NodalConstraints constraints, double friction_coefficient,
                 NodalDamping damping, std::vector<ConstitutiveModel> models);

  /// The switch from the elastic geostatic state to the failure-stage models: one
  /// update with a zero strain increment on every Gauss point, which returns stresses
  /// outside the yield surface to it. Returns how many points were returned.
  std::size_t return_to_yield_surface(FemState& state) const;

  /// Courant step dt = C·min_e(l_e/c_p) of the reference (small strain) or current
  /// (updated Lagrangian) geometry.
  double stable_time_step(const FemState& state, double courant);

  /// One step of length dt. Returns −1, or for updated Lagrangian the first element the
  /// step would invert (det J ≤ 0), in which case `state` is left unchanged.
  Index step(FemState& state, double dt);

  /// Number of Gauss points that yielded in the last step.
  std::size_t last_yielded_count() const { return yielded_count_; }

  /// The velocity at the state's time, v(t_n) = v_{n−1/2} + (dt/2) F_n/m: a half step of
  /// the same constrained nodal update with the forces of the current state (`dt` the
  /// length of the step that led to it). Energies use it so that kinetic and potential
  /// energy refer to the same instant.
  void synchronised_velocity(const FemState& state, double dt, std::vector<Vec2>& velocity);

  const NodalConstraints& constraints() const { return constraints_; }

 private:
  const ElementGeometry& geometry_for(const FemState& state);
  void update_nodes(FemState& state, double dt) const;
  Vec2 nodal_force(Index node) const;

  const FemModel& model_;
  NodalConstraints constraints_;
  double friction_coefficient_;
  NodalDamping damping_;
  std::vector<ConstitutiveModel> models_;
  bool updated_lagrangian_;

  std::vector<Vec2> element_force_;  ///< n_elements × nodes_per_element
  std::size_t yielded_count_ = 0;
  // Updated Lagrangian: the current geometry, valid for state step `geometry_step_`,
  // and the nodal state saved before a step that might invert an element.
  ElementGeometry current_;
  Index geometry_step_ = -1;
  std::vector<Vec2> coordinates_;
  std::vector<Vec2> saved_displacement_, saved_velocity_, saved_acceleration_;
};

}  // namespace slide::fem
