// The explicit velocity update of one node, shared by the FE nodes and the MPM grid
// nodes so that both phases apply boundary conditions, Coulomb base friction and
// damping with exactly the same algorithm (METHOD.md §3 and §5).
//
// Given the node's lumped mass m, its velocity v at the start of the step and the
// unbalanced force F (external + internal, without reactions), one step of length dt:
//   1. damping: F ← F − α_M m v (mass-proportional Rayleigh),
//               F_i ← F_i − α |F_i| sign(v_i) (local, Cundall; per component);
//   2. trial velocity v* = v + dt F / m;
//   3. constraints, in the order fixed, roller, friction:
//      fixed:    v* = 0;
//      roller:   the normal component of v* is removed (bilateral: no separation);
//      friction: the normal component is removed as for a roller; the normal impulse
//                that took, m v*_n (v*_n = v*·n > 0 when the node pushes into the
//                boundary, n the outward normal of the body), bounds the tangential
//                impulse by μ m v*_n: if |v*_t| ≤ μ v*_n the node sticks (v*_t = 0),
//                otherwise it slips and |v*_t| shrinks by μ v*_n. A node pulling away
//                (v*_n ≤ 0) gets no friction. This is Coulomb stick/slip on the
//                tangential nodal force, |F_t| ≤ μ N with N = m v*_n / dt.
#pragma once

#include <span>

#include "common/mesh.hpp"
#include "common/types.hpp"

namespace slide {

/// A velocity constraint on one node: what, and the outward normal of the body there.
struct NodalConstraint {
  BoundaryCondition condition = BoundaryCondition::free;
  Vec2 normal = Vec2::Zero();
};

struct NodalDamping {
  double rayleigh_mass = 0.0;  ///< α_M, 1/s
  double local = 0.0;          ///< Cundall α, –
};

/// Steps 1–2: the damped trial velocity v* = v + dt (F − damping) / m.
Vec2 damped_trial_velocity(double mass, const Vec2& velocity, const Vec2& force, double dt,
                           const NodalDamping& damping);

/// Step 3 for one constraint; `friction_coefficient` is used by friction only.
Vec2 apply_constraint(const NodalConstraint& constraint, double friction_coefficient,
                      const Vec2& trial_velocity);

/// Step 3 for all the constraints of a node (a corner belongs to two boundaries):
/// fixed first, then rollers, then friction.
Vec2 apply_constraints(std::span<const NodalConstraint> constraints, double friction_coefficient,
                       const Vec2& trial_velocity);

}  // namespace slide
