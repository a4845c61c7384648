#include "common/physics/nodal_update.hpp"

#include <algorithm>
#include <cmath>

namespace slide {

namespace {

int precedence(BoundaryCondition condition) {
  switch (condition) {
    case BoundaryCondition::fixed:
      return 0;
    case BoundaryCondition::roller:
      return 1;
    case BoundaryCondition::friction:
      return 2;
    case BoundaryCondition::free:
      return 3;
  }
  return 3;
}

}  // namespace

Vec2 apply_constraint(const NodalConstraint& constraint, double friction_coefficient,
                      const Vec2& trial_velocity, const ContactGap& gap) {
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

Vec2 apply_constraints(std::span<const NodalConstraint> constraints, double friction_coefficient,
                       const Vec2& trial_velocity, const ContactGap& gap) {
  Vec2 v = trial_velocity;
  for (int level = 0; level < 3; ++level) {
    for (const auto& constraint : constraints) {
      if (precedence(constraint.condition) == level) {
        v = apply_constraint(constraint, friction_coefficient, v, gap);
      }
    }
  }
  return v;
}

double contact_gap(const NodalConstraint& constraint, const Vec2& displacement) {
  return std::max(0.0, -displacement.dot(constraint.normal));
}

}  // namespace slide
