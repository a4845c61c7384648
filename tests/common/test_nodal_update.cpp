// The shared nodal velocity update: constraints, Coulomb friction, damping.
#include <array>
#include <cmath>

#include <gtest/gtest.h>

#include "common/physics/nodal_update.hpp"

namespace slide {
namespace {

const NodalConstraint base{BoundaryCondition::friction, Vec2(0.0, -1.0)};
const NodalConstraint left_wall{BoundaryCondition::roller, Vec2(-1.0, 0.0)};

TEST(NodalUpdate, FrictionSlipRemovesMuTimesTheNormalImpulse) {
  const double m = 2.0, dt = 0.01, mu = 0.5;
  const Vec2 trial = damped_trial_velocity(m, Vec2(3.0, 0.0), Vec2(0.0, -m * 9.81), dt, {});
  const Vec2 v = apply_constraint(base, mu, trial);
  EXPECT_DOUBLE_EQ(v.y(), 0.0);
  EXPECT_NEAR(v.x(), 3.0 - mu * 9.81 * dt, 1e-14);
}

TEST(NodalUpdate, FrictionSticksWhenTheTangentialImpulseIsWithinTheCone) {
  const Vec2 v = apply_constraint(base, 0.5, Vec2(0.04, -0.1));
  EXPECT_EQ(v, Vec2::Zero());
  // Just outside the cone it slips by exactly the cone's share.
  const Vec2 w = apply_constraint(base, 0.5, Vec2(0.06, -0.1));
  EXPECT_NEAR(w.x(), 0.01, 1e-15);
  EXPECT_EQ(w.y(), 0.0);
}

TEST(NodalUpdate, NodePullingAwayFromTheBaseIsLeftFree) {
  const Vec2 v = apply_constraint(base, 0.5, Vec2(2.0, 0.3));
  EXPECT_EQ(v, Vec2(2.0, 0.3));
}

TEST(NodalUpdate, LiftedNodeLandsExactlyOnTheBaseAndOnlyTheExcessImpulseBrakes) {
  // 1 mm above the base, falling at 3 m/s with dt = 1 ms: 2 m/s of the normal speed
  // would carry it below the base; that excess is the normal impulse per unit mass.
  const ContactGap gap{contact_gap(base, Vec2(0.0, 1e-3)), 1e-3};
  EXPECT_DOUBLE_EQ(gap.gap, 1e-3);
  const Vec2 slipping = apply_constraint(base, 0.5, Vec2(4.0, -3.0), gap);
  EXPECT_DOUBLE_EQ(slipping.y(), -1.0);  // lands: 1 mm in 1 ms
  EXPECT_DOUBLE_EQ(slipping.x(), 3.0);   // 4 − μ·2
  const Vec2 sticking = apply_constraint(base, 0.5, Vec2(0.5, -3.0), gap);
  EXPECT_EQ(sticking, Vec2(0.0, -1.0));
  // Falling too slowly to reach the base in this step: free.
  EXPECT_EQ(apply_constraint(base, 0.5, Vec2(4.0, -0.5), gap), Vec2(4.0, -0.5));
}

TEST(NodalUpdate, BlockSlidingOnTheBaseStopsAfterVSquaredOverTwoMuG) {
  // One node carrying a rigid block: the discrete stopping distance converges to
  // v0²/(2μg) as dt → 0 (the error is one step's travel).
  const double m = 1.0, mu = 0.466, v0 = 5.0, dt = 1e-4;
  Vec2 x = Vec2::Zero(), v(v0, 0.0);
  const std::array<NodalConstraint, 1> constraints{base};
  for (int step = 0; step < 1000000 && v.x() > 0.0; ++step) {
    v = apply_constraints(constraints, mu,
                          damped_trial_velocity(m, v, Vec2(0.0, -m * 9.81), dt, {}));
    x += dt * v;
  }
  const double expected = v0 * v0 / (2.0 * mu * 9.81);
  EXPECT_NEAR(x.x(), expected, v0 * dt);
}

TEST(NodalUpdate, CornerNodeWithRollerAndFrictionIsHeld) {
  const std::array<NodalConstraint, 2> corner{base, left_wall};
  EXPECT_EQ(apply_constraints(corner, 0.3, Vec2(-1.0, -2.0)), Vec2::Zero());
}

TEST(NodalUpdate, RollerOnAnInclinedBoundaryKeepsOnlyTheTangentialComponent) {
  const Vec2 n = Vec2(1.0, -1.0).normalized();
  const Vec2 v = apply_constraint({BoundaryCondition::roller, n}, 0.0, Vec2(2.0, 1.0));
  EXPECT_NEAR(v.dot(n), 0.0, 1e-15);
  EXPECT_NEAR(v.x(), 1.5, 1e-15);
  EXPECT_NEAR(v.y(), 1.5, 1e-15);
}

TEST(NodalUpdate, LocalDampingOpposesTheVelocityByAlphaTimesTheForce) {
  const NodalDamping damping{0.0, 0.2};
  const Vec2 v = damped_trial_velocity(1.0, Vec2(1.0, -1.0), Vec2(10.0, 10.0), 0.1, damping);
  EXPECT_NEAR(v.x(), 1.0 + 0.1 * (10.0 - 2.0), 1e-14);
  EXPECT_NEAR(v.y(), -1.0 + 0.1 * (10.0 + 2.0), 1e-14);
}

TEST(NodalUpdate, RayleighMassDampingDecaysFreeMotionExponentially) {
  const double alpha = 2.0, dt = 1e-5;
  Vec2 v(1.0, 0.0);
  for (int step = 0; step < 100000; ++step) {
    v = damped_trial_velocity(3.0, v, Vec2::Zero(), dt, {alpha, 0.0});
  }
  EXPECT_NEAR(v.x(), std::exp(-alpha * 1.0), 1e-4);
}

}  // namespace
}  // namespace slide
