// The explicit velocity update of one node, shared by the FE nodes and the MPM grid
// nodes so that both phases apply boundary conditions, Coulomb base friction and
// damping with exactly the same algorithm (docs/method.md §3 and §5).
//
// Given the node's lumped mass m, its velocity v at the start of the step and the
// unbalanced force F (external + internal, without reactions), one step of length dt:
//   1. damping: F ← F − α_M m v (mass-proportional Rayleigh),
//               F_i ← F_i − α |F_i| sign(v_i) (local, Cundall; per component);
//   2. trial velocity v* = v + dt F / m;
//   3. constraints, in the order fixed, roller, friction:
//      fixed:    v* = 0;
//      roller:   the normal component of v* is removed (bilateral: no separation);
//      friction: a unilateral Coulomb contact. With n the outward normal of the body
//                and v*_n = v*·n > 0 when the node moves into the boundary, a node
//                that stays clear of the boundary in this step (v*_n dt ≤ gap, which
//                includes every node pulling away) is left free: soil may lift off
//                the base. Otherwise the normal motion stops on the boundary
//                (v_n = gap/dt) and the normal impulse that took, m (v*_n − gap/dt),
//                bounds the tangential one: if |v*_t| ≤ μ (v*_n − gap/dt) the node
//                sticks, otherwise |v*_t| shrinks by that much. This is Coulomb
//                stick/slip on the tangential nodal force, |F_t| ≤ μ N.
//
// Why unilateral: a bilateral contact (the node held down when pulled up) with friction
// only while pushing rectifies the vibration of an elastic body into extra friction; a
// block sliding at μ = 0.5 then stopped after 56 % of the Coulomb distance v0²/(2μg).
// Grid nodes of the MPM base and FE base nodes resting on it have gap = 0; an FE base
// node that has lifted off passes its gap so that it lands exactly on the base.
#pragma once

#include <cmath>
#include <span>

#include "common/base/types.hpp"
#include "common/geometry/mesh.hpp"

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
/// Inline: it runs once per node and step in both solvers.
inline Vec2 damped_trial_velocity(double mass, const Vec2& velocity, const Vec2& force, double dt,
                                  const NodalDamping& damping) {
  Vec2 f = force - damping.rayleigh_mass * mass * velocity;
  if (damping.local > 0.0) {
    auto sign = [](double x) { return x > 0.0 ? 1.0 : (x < 0.0 ? -1.0 : 0.0); };
    f.x() -= damping.local * std::abs(f.x()) * sign(velocity.x());
    f.y() -= damping.local * std::abs(f.y()) * sign(velocity.y());
  }
  return velocity + (dt / mass) * f;
}

/// How far a node is from a frictional boundary and how long the step is: the node may
/// close `gap` (m, ≥ 0) freely within the step of length `dt`.
struct ContactGap {
  double gap = 0.0;
  double dt = 1.0;
};

/// Step 3 for one constraint; `friction_coefficient` and `gap` are used by friction only.
/// Inline, like the trial velocity: a frictional base is tested at every node of a model
/// above it, and most nodes leave at the first test.
inline Vec2 apply_constraint(const NodalConstraint& constraint, double friction_coefficient,
                             const Vec2& trial_velocity, const ContactGap& gap = {}) {
  const Vec2& n = constraint.normal;
  switch (constraint.condition) {
    case BoundaryCondition::free:
      return trial_velocity;
    case BoundaryCondition::fixed:
      return Vec2::Zero();
    case BoundaryCondition::roller:
      return trial_velocity - trial_velocity.dot(n) * n;
    case BoundaryCondition::friction: {
      const double normal_speed = trial_velocity.dot(n);
      const double closing_speed = gap.gap / gap.dt;
      if (normal_speed <= closing_speed) return trial_velocity;
      const Vec2 tangential = trial_velocity - normal_speed * n;
      const Vec2 landing = closing_speed * n;
      const double slip_speed = tangential.norm();
      const double friction_speed = friction_coefficient * (normal_speed - closing_speed);
      if (slip_speed <= friction_speed) return landing;
      return landing + tangential * (1.0 - friction_speed / slip_speed);
    }
  }
  return trial_velocity;
}

/// Step 3 for all the constraints of a node (a corner belongs to two boundaries):
/// fixed first, then rollers, then friction.
Vec2 apply_constraints(std::span<const NodalConstraint> constraints, double friction_coefficient,
                       const Vec2& trial_velocity, const ContactGap& gap = {});

/// The gap of a node from a frictional boundary it started on, given its displacement:
/// how far it has moved away along the outward normal (0 when on or past the boundary).
double contact_gap(const NodalConstraint& constraint, const Vec2& displacement);

}  // namespace slide
