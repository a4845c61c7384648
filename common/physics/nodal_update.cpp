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
