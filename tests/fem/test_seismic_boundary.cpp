// The seismic boundaries of fem/seismic_boundary.hpp on small meshes: dashpot lengths,
// tie pairing, and the static reactions the released supports keep.
#include <cmath>

#include <gtest/gtest.h>

#include "common/base/error.hpp"
#include "fem/explicit_dynamics.hpp"
#include "fem/fem_model.hpp"
#include "fem/geostatic.hpp"
#include "fem/model_setup.hpp"
#include "fem/seismic_boundary.hpp"
#include "tests/support/meshes.hpp"
#include "tools/synthetic/soil.hpp"

namespace slide::fem {
namespace {

struct Column {
  FemModel model;
  FemState geostatic;
  GroundMotion motion;
};

/// The geostatic state of `model` on rollers at its left, right and base.
FemState geostatic_on_rollers(const FemModel& model) {
  FemState state = make_rest_state(model);
  const BoundaryTable rollers{{"left", BoundaryCondition::roller},
                              {"right", BoundaryCondition::roller},
                              {"base", BoundaryCondition::roller}};
  solve_geostatic(model, make_constraints(model.mesh, rollers, "test"), state);
  return state;
}

/// A 2 m wide, 4 m high elastic column of 0.5 m quads in geostatic equilibrium on
/// rollers, and a motion at rest (the boundaries do not depend on it).
Column column() {
  Column c{make_model(testing::rectangle_mesh(ElementType::quad4_1gp, 4, 8, 2.0, 4.0),
                      {synthetic::soil()}, Kinematics::small_strain, 1.0),
           {},
           GroundMotion(AccelerationRecord{{0.0, 1.0}, {0.0, 0.0}}, {}, 0.0, 0.1, false)};
  c.geostatic = geostatic_on_rollers(c.model);
  return c;
}

MotionSpec compliant_tied() {
  MotionSpec spec;
  spec.base = SeismicBase::compliant;
  spec.lateral = LateralBoundary::tied;
  spec.rock_density = 2000.0;
  spec.rock_shear_wave_speed = 300.0;
  return spec;
}

// The base's dashpots share its 2 m by tributary length (the corners 0.25 m, the inner
// nodes 0.5 m): Σ c = ρ_r V_s,r · 2 m; the incident force per unit velocity is twice the
// dashpot for an incident input.
TEST(SeismicBoundary, CompliantBaseDashpotsSumToTheImpedanceTimesTheBase) {
  const Column c = column();
  const MotionSpec spec = compliant_tied();
  const SeismicBoundary b =
      make_seismic_boundary(c.model, spec, c.motion, support_reactions(c.model, c.geostatic));
  double dashpot = 0.0, incident = 0.0;
  for (std::size_t n = 0; n < b.dashpot.size(); ++n) {
    dashpot += b.dashpot[n].x();
    incident += b.incident[n].x();
    EXPECT_EQ(b.dashpot[n].y(), 0.0);  // no vertical motion: the roller stays
  }
  const double impedance = spec.rock_density * spec.rock_shear_wave_speed;
  EXPECT_NEAR(dashpot, impedance * 2.0, 1e-9 * impedance);
  EXPECT_NEAR(incident, 2.0 * impedance * 2.0, 1e-9 * impedance);
  EXPECT_FALSE(b.dashpots_in_base_frame);
}

// Tied sides pair every node of the left edge with the right node at its elevation (the
// compliant base's corners too), and keep each roller's horizontal reaction: in a level
// column a pair's two reactions cancel, so the pair starts in equilibrium.
TEST(SeismicBoundary, TiedSidesPairEqualElevationsAndKeepCancellingReactions) {
  const Column c = column();
  const std::vector<Vec2> reactions = support_reactions(c.model, c.geostatic);
  const SeismicBoundary b = make_seismic_boundary(c.model, compliant_tied(), c.motion, reactions);
  ASSERT_EQ(b.tied.size(), 9u);  // 8 rows: 9 nodes a side
  EXPECT_TRUE(b.tie_vertical);
  EXPECT_EQ(b.viscous_side_nodes, 0);
  double largest = 0.0;
  for (const auto& [left, right] : b.tied) {
    const auto l = static_cast<std::size_t>(left), r = static_cast<std::size_t>(right);
    EXPECT_DOUBLE_EQ(c.model.mesh.nodes[l].y(), c.model.mesh.nodes[r].y());
    EXPECT_DOUBLE_EQ(b.static_force[l].x(), reactions[l].x());
    largest = std::max(largest, std::abs(reactions[l].x()));
    EXPECT_NEAR(b.static_force[l].x() + b.static_force[r].x(), 0.0, 1e-9 * largest);
  }
  EXPECT_GT(largest, 0.0);  // the rollers did carry the K0 thrust
}

// A rigid base prescribes its nodes: its corners are in no pair; viscous sides get
// ρ V_p L normal and ρ V_s L tangential dashpots with the soil's speeds.
TEST(SeismicBoundary, RigidBaseCornersAreNotTiedAndViscousSidesUseTheSoilsSpeeds) {
  const Column c = column();
  const std::vector<Vec2> reactions = support_reactions(c.model, c.geostatic);
  MotionSpec spec;
  spec.lateral = LateralBoundary::tied_horizontal;
  const SeismicBoundary tied = make_seismic_boundary(c.model, spec, c.motion, reactions);
  EXPECT_EQ(tied.tied.size(), 8u);
  EXPECT_FALSE(tied.tie_vertical);
  spec.lateral = LateralBoundary::viscous;
  const SeismicBoundary viscous = make_seismic_boundary(c.model, spec, c.motion, reactions);
  EXPECT_EQ(viscous.viscous_side_nodes, 16);
  const Material& m = c.model.materials[0];
  const double vs = std::sqrt(m.shear_modulus() / m.density);
  double normal = 0.0, tangential = 0.0;
  for (const Index n : c.model.mesh.node_sets[0].nodes) {  // left
    normal += viscous.dashpot[static_cast<std::size_t>(n)].x();
    tangential += viscous.dashpot[static_cast<std::size_t>(n)].y();
  }
  // The left edge's 4 m less the base corner's half cell (a rigid base's node).
  EXPECT_NEAR(normal, m.density * m.p_wave_speed() * 3.75, 1e-9 * normal);
  EXPECT_NEAR(tangential, m.density * vs * 3.75, 1e-9 * tangential);
}

/// A saturated sand column of column()'s mesh (n = 0.4, k = 1e-5 m/s), the water table at
/// `level`, its interior nodes moved when `distorted`, in geostatic equilibrium on rollers.
struct SaturatedColumn {
  Material sand;
  FemModel model;
  FemState state;
};
SaturatedColumn saturated_column(double level, double bulk_modulus, bool distorted) {
  Material sand = synthetic::soil(MaterialModel::linear_elastic, 2000.0);
  sand.porosity = 0.4;
  sand.conductivity_x = sand.conductivity_y = 1e-5;
  WaterSpec water;
  water.level = level;
  water.bulk_modulus = bulk_modulus;
  Mesh mesh = testing::rectangle_mesh(ElementType::quad4_1gp, 4, 8, 2.0, 4.0);
  if (distorted) testing::distort_interior(mesh, 0.5, 0.2);
  SaturatedColumn c{
      sand,
      make_model(std::move(mesh), {sand}, Kinematics::small_strain, 1.0, gravity_vector(), water),
      {}};
  c.state = geostatic_on_rollers(c.model);
  return c;
}

// Tied sides of a saturated column (fem/pore_fluid.hpp) share their pore pressure as
// they share their motion: on a distorted mesh, whose two sides would otherwise drift
// apart, every pair of side elements ends a second of shaking with one pressure, and the
// shaking did move the water.
TEST(SeismicBoundary, TiedSidesShareTheirPorePressure) {
  auto [sand, model, state] = saturated_column(4.0, 0.2e9, true);
  AccelerationRecord shaking;
  for (int k = 0; k <= 100; ++k) {
    shaking.time.push_back(0.01 * k);
    shaking.acceleration.push_back(2.0 * std::sin(2.0 * 3.141592653589793 * 5.0 * 0.01 * k));
  }
  const GroundMotion motion(shaking, {}, 0.0, 1e-4, true);
  const SeismicBoundary b =
      make_seismic_boundary(model, compliant_tied(), motion, support_reactions(model, state));
  std::vector<ConstitutiveModel> models{ConstitutiveModel::from(sand)};
  ExplicitSolver solver(model,
                        make_constraints(model.mesh, {{"base", BoundaryCondition::free}}, "test"),
                        0.0, {}, models);
  solver.set_seismic(&b);
  const double dt = solver.stable_time_step(state, 0.5);
  while (state.time < 1.0) solver.step(state, dt);
  double excess = 0.0;
  for (std::size_t n = 0; n < state.pore_pressure.size(); ++n) {
    excess = std::max(excess, std::abs(state.pore_pressure[n] - state.static_pore_pressure[n]));
  }
  EXPECT_GT(excess, 100.0);                              // Pa: the shaking moved the water
  ASSERT_EQ(b.tied_elements.size(), b.tied.size() - 1);  // every side element paired
  for (const auto& [left, right] : b.tied_elements) {
    EXPECT_EQ(state.element_pore_pressure[static_cast<std::size_t>(left)],
              state.element_pore_pressure[static_cast<std::size_t>(right)])
        << left << " " << right;
  }
}

// Released to viscous sides, a saturated column at rest stays at rest: the sides' static
// forces carry the water's thrust as well as the skeleton's (support_reactions with the
// pore pressure), and the dashpots only act on motion. Without the water's share the
// sides would push the column in by the hydrostatic thrust.
TEST(SeismicBoundary, ViscousSidesHoldASaturatedColumnAtRest) {
  auto [sand, model, state] = saturated_column(3.0, 2.2e9, false);
  const GroundMotion still(AccelerationRecord{{0.0, 1.0}, {0.0, 0.0}}, {}, 0.0, 1e-4, false);
  MotionSpec spec;
  spec.base = SeismicBase::rigid;
  spec.lateral = LateralBoundary::viscous;
  const SeismicBoundary b =
      make_seismic_boundary(model, spec, still, support_reactions(model, state));
  ExplicitSolver solver(model,
                        make_constraints(model.mesh, {{"base", BoundaryCondition::fixed}}, "test"),
                        0.0, {}, {ConstitutiveModel::from(sand)});
  solver.set_seismic(&b);
  const double dt = solver.stable_time_step(state, 0.5);
  for (int i = 0; i < 500; ++i) solver.step(state, dt);
  double speed = 0.0;
  for (const Vec2& v : state.velocity) speed = std::max(speed, v.norm());
  EXPECT_LT(speed, 1e-9);  // without the water's share: 6.4e-3 m/s after 500 steps
}

}  // namespace
}  // namespace slide::fem
