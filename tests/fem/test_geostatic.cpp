// Stage 1: the geostatic column, σyy = −ρ g (H − y), σxx = σzz = K0 σyy (docs/method.md §3).
//
// The discrete solution of the roller-bounded column is one-dimensional and nodally
// exact (consistent gravity load), so each element carries the exact strain of its
// mid-height: the element-centre stress is exact to round-off. A Gauss point at height
// y_gp ≠ y_centre therefore errs by ρ g |y_gp − y_centre|:
//   quad4-1gp  (centre):             0, asserted to round-off;
//   quad4-2×2  (y_c ± h/(2√3)):      ρ g h /(2√3) exactly;
//   tri3       (centroid, y_c ± h/6): about ρ g h / 6; splitting the cells into
//              triangles spreads the load unevenly over the nodes near the sides (and,
//              with the cases' chequerboard diagonals, in the interior too), which adds
//              a local error of the same order.
// Both errors are O(h): the convergence order is 1. On geostatic-4x4 (h = 0.25 m,
// H = 4 m) ρ g h/(2√3) is 1.80 % of ρ g H, so the 1 % bound holds there for the
// element-mean stress, at the Gauss points of quad4-1gp (0) and of tri3 (0.53 %), not
// at those of quad4-2×2; on column-short (h = 1 m, H = 40 m) it holds at every Gauss
// point of every element type.
#include <cmath>
#include <cstdio>
#include <numbers>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "common/base/error.hpp"
#include "common/input/case_file.hpp"
#include "common/input/mesh_generation.hpp"
#include "fem/element_kernels.hpp"
#include "fem/fem_model.hpp"
#include "fem/geostatic.hpp"
#include "fem/model_setup.hpp"
#include "tests/support/eigen_checks.hpp"
#include "tests/support/meshes.hpp"
#include "tools/synthetic/soil.hpp"

namespace slide::fem {
namespace {

const std::filesystem::path cases_dir = std::filesystem::path(SLIDE_SOURCE_DIR) / "cases";

struct ColumnErrors {
  double gauss = 0.0;         ///< max |σ − σ_exact| over Gauss points and components
  double element_mean = 0.0;  ///< same for the element means
  double shear = 0.0;         ///< max |σxy|
  double rho_g_h = 0.0;       ///< ρ g H
};

ColumnErrors geostatic_errors(const FemModel& model, const BoundaryTable& boundaries) {
  FemState state = make_rest_state(model);
  solve_geostatic(model, make_constraints(model.mesh, boundaries, "test"), state);
  const Material& m = model.materials[0];
  const double rho_g = m.density * gravity_acceleration;
  const double height = model.extent.height;
  const auto exact = [&](double y) {
    const double syy = -rho_g * (height - y);
    return Vec4(m.k0() * syy, syy, m.k0() * syy, 0.0);
  };
  ColumnErrors errors;
  errors.rho_g_h = rho_g * height;
  const auto n_gauss = static_cast<std::size_t>(model.gauss_per_element());
  for (Index e = 0; e < model.element_count(); ++e) {
    const ElementNodes x = model.mesh.element_nodes(e, model.mesh.nodes);
    Vec4 mean = Vec4::Zero();
    Vec2 centroid = Vec2::Zero();
    for (std::size_t p = 0; p < n_gauss; ++p) {
      const std::size_t gp = static_cast<std::size_t>(e) * n_gauss + p;
      const Vec2 xg = map_to_physical(model.mesh.shape(), x, model.rule.local[p]);
      const Vec4 error = state.stress[gp] - exact(xg.y());
      errors.gauss = std::max(errors.gauss, testing::max_abs(error.head<3>()));
      errors.shear = std::max(errors.shear, std::abs(state.stress[gp][3]));
      mean += state.stress[gp] / static_cast<double>(n_gauss);
      centroid += xg / static_cast<double>(n_gauss);
    }
    const Vec4 mean_error = mean - exact(centroid.y());
    errors.element_mean = std::max(errors.element_mean, testing::max_abs(mean_error.head<3>()));
  }
  // Displacements, velocities and strains are reset: t = 0 is undeformed.
  for (const Vec2& u : state.displacement) EXPECT_EQ(u, Vec2::Zero());
  for (const Vec4& e : state.strain) EXPECT_EQ(e, Vec4::Zero());
  return errors;
}

ColumnErrors case_errors(const std::string& name, ElementType type) {
  Case c = load_case(cases_dir / name / "case.toml");
  c.mesh.element_type = type;
  const FemModel model =
      make_model(build_mesh(c), c.materials, Kinematics::small_strain, c.fem.hourglass_coefficient);
  return geostatic_errors(model, c.fem.geostatic_boundaries);
}

TEST(Geostatic, Geostatic4x4IsExactAtTheCentresOfOnePointQuads) {
  const ColumnErrors e = case_errors("geostatic-4x4", ElementType::quad4_1gp);
  EXPECT_LT(e.gauss, 1e-12 * e.rho_g_h);
  EXPECT_LT(e.shear, 1e-9 * e.rho_g_h);
}

TEST(Geostatic, Geostatic4x4GaussPointErrorsAreTheKnownOffsets) {
  // h = 0.25 m, H = 4 m: the 2×2 Gauss points sit h/(2√3) from the centre of their
  // element, so they err by exactly ρ g h/(2√3) = 1.80 % of ρ g H; the element means
  // are exact. This offset is inherent to the bilinear element at this h, not a defect.
  const double h = 0.25;
  const ColumnErrors quad = case_errors("geostatic-4x4", ElementType::quad4_2x2);
  const double rho_g = 1700.0 * gravity_acceleration;
  RecordProperty("quad4_2x2_gauss_error_over_rho_g_H",
                 fmt::format("{:.5f}", quad.gauss / quad.rho_g_h));
  EXPECT_NEAR(quad.gauss, rho_g * h / (2.0 * std::sqrt(3.0)), 1e-9 * quad.rho_g_h);
  EXPECT_NEAR(quad.gauss / quad.rho_g_h, (h / 4.0) / (2.0 * std::sqrt(3.0)), 1e-9);
  EXPECT_LT(quad.element_mean, 1e-12 * quad.rho_g_h);
  // tri3: centroids h/6 from the row centre plus the uneven load split of the diagonals
  // (see the top of this file); measured 0.53 % of ρ g H, held to 1 %.
  const ColumnErrors tri = case_errors("geostatic-4x4", ElementType::tri3);
  RecordProperty("tri3_gauss_error_over_rho_g_H", fmt::format("{:.5f}", tri.gauss / tri.rho_g_h));
  EXPECT_LT(tri.gauss, 0.01 * tri.rho_g_h) << tri.gauss / tri.rho_g_h;
  EXPECT_LT(tri.element_mean, 0.01 * tri.rho_g_h);
}

TEST(Geostatic, ColumnShortWithinOnePercentAtEveryGaussPoint) {
  for (const auto type : {ElementType::quad4_1gp, ElementType::quad4_2x2, ElementType::tri3}) {
    SCOPED_TRACE(to_string(type));
    const ColumnErrors e = case_errors("column-short", type);
    EXPECT_LT(e.gauss, 0.01 * e.rho_g_h);
    EXPECT_LT(e.shear, 0.01 * e.rho_g_h);
  }
}

TEST(Geostatic, GaussPointErrorConvergesAtFirstOrder) {
  // A 2 m × 4 m column meshed with h = 0.5, 0.25, 0.125 m.
  for (const auto type : {ElementType::quad4_2x2, ElementType::tri3}) {
    SCOPED_TRACE(to_string(type));
    std::vector<double> errors;
    for (int refinement : {1, 2, 4}) {
      Mesh mesh = testing::rectangle_mesh(type, 4 * refinement, 8 * refinement, 2.0, 4.0);
      const FemModel model =
          make_model(std::move(mesh), {synthetic::soil()}, Kinematics::small_strain, 1.0);
      const BoundaryTable rollers{{"left", BoundaryCondition::roller},
                                  {"right", BoundaryCondition::roller},
                                  {"base", BoundaryCondition::roller}};
      errors.push_back(geostatic_errors(model, rollers).gauss);
    }
    for (std::size_t i = 1; i < errors.size(); ++i) {
      const double order = std::log2(errors[i - 1] / errors[i]);
      RecordProperty(std::string(to_string(type)) + "_order_" + std::to_string(i),
                     std::to_string(order));
      EXPECT_NEAR(order, 1.0, 0.1) << "refinement " << i;
    }
  }
}

TEST(Geostatic, TiedSidesMakeTheInfiniteSlope) {
  // A column on a 10° incline (gravity turned), its sides tied, its base fixed: the
  // infinite slope, whose horizontal planes carry σyy = −ρ g cos θ (H − y) and
  // σxy = ρ g sin θ (H − y) (equilibrium alone: the column is one-dimensional), σxx = σzz
  // = K0 σyy (no lateral strain). One-point quads are exact at their centres. Without
  // the ties the free sides let the column bend: the shear is far from the slope's.
  const double theta = 10.0 * std::numbers::pi / 180.0;
  const Vec2 gravity(gravity_acceleration * std::sin(theta),
                     -gravity_acceleration * std::cos(theta));
  Mesh mesh = testing::rectangle_mesh(ElementType::quad4_1gp, 2, 20, 1.0, 10.0);
  const FemModel model =
      make_model(std::move(mesh), {synthetic::soil()}, Kinematics::small_strain, 1.0, gravity);
  const BoundaryTable boundaries{{"left", BoundaryCondition::free},
                                 {"right", BoundaryCondition::free},
                                 {"base", BoundaryCondition::fixed}};
  const auto pairs = pair_sides(model, "test");
  EXPECT_EQ(pairs.size(), 21u);
  const Material& m = model.materials[0];
  const double rho_g = m.density * gravity_acceleration;
  auto worst = [&](bool tied) {
    FemState state = make_rest_state(model);
    solve_geostatic(model, make_constraints(model.mesh, boundaries, "test"), state,
                    tied ? std::span<const std::pair<Index, Index>>(pairs)
                         : std::span<const std::pair<Index, Index>>{});
    double error = 0.0;
    for (Index e = 0; e < model.element_count(); ++e) {
      const ElementNodes x = model.mesh.element_nodes(e, model.mesh.nodes);
      const double y = x.col(1).mean();
      const double depth = model.extent.height - y;
      const double syy = -rho_g * std::cos(theta) * depth;
      const Vec4 exact(m.k0() * syy, syy, m.k0() * syy, rho_g * std::sin(theta) * depth);
      error = std::max(error,
                       (state.stress[static_cast<std::size_t>(e)] - exact).cwiseAbs().maxCoeff());
    }
    return error / (rho_g * model.extent.height);
  };
  const double tied = worst(true);
  const double free = worst(false);
  std::printf(
      "infinite slope of 10°: largest stress error %.2e (tied), %.2e (free sides) of ρ g H\n", tied,
      free);
  EXPECT_LT(tied, 1e-10);
  EXPECT_GT(free, 1e-2);
}

TEST(Geostatic, FreeRigidBodyMotionIsAnError) {
  Mesh mesh = testing::rectangle_mesh(ElementType::quad4_1gp, 2, 2, 2.0, 2.0);
  const FemModel model =
      make_model(std::move(mesh), {synthetic::soil()}, Kinematics::small_strain, 1.0);
  FemState state = make_rest_state(model);
  // Only the base roller: the column may slide sideways.
  const BoundaryTable base_only{{"base", BoundaryCondition::roller}};
  EXPECT_THROW(solve_geostatic(model, make_constraints(model.mesh, base_only, "test"), state),
               Error);
}

TEST(Geostatic, UnknownBoundaryNameIsAnError) {
  const Mesh mesh = testing::rectangle_mesh(ElementType::quad4_1gp, 2, 2, 2.0, 2.0);
  try {
    make_constraints(mesh, {{"toe", BoundaryCondition::roller}},
                     "case.toml: fem.failure.boundaries");
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()),
              "case.toml: fem.failure.boundaries: boundary \"toe\" is not a node set of the mesh "
              "(node sets: left, right, base, top)");
  }
}

}  // namespace
}  // namespace slide::fem
