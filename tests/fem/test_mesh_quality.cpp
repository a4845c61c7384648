// Mesh quality, the recommended transfer zone and the energies (METHOD.md §3).
#include <cmath>

#include <gtest/gtest.h>

#include "fem/fem_model.hpp"
#include "fem/fem_output.hpp"
#include "fem/mesh_quality.hpp"
#include "fem_test_support.hpp"

namespace slide::fem {
namespace {

FemModel block(ElementType type) {
  return make_model(testing::rectangle_mesh(type, 4, 2, 4.0, 2.0), {testing::soil()},
                    Kinematics::small_strain, 1.0);
}

TEST(MeshQuality, JacobianRatioAndEpsQOfAHomogeneousDeformation) {
  // x = F X with F = [[1.1, 0.2], [0, 0.9]]: det F = 0.99 everywhere; the strain
  // [εxx, εyy, εzz, γxy] = [0.1, −0.1, 0, 0.2] has e = ε − tr/3 with tr = 0, so
  // εq = sqrt(2/3 (0.01 + 0.01 + 2·0.01)) = sqrt(0.08/3).
  for (const auto type : {ElementType::quad4_1gp, ElementType::quad4_2x2, ElementType::tri3}) {
    const FemModel model = block(type);
    FemState state = make_rest_state(model);
    Mat2 f;
    f << 1.1, 0.2, 0.0, 0.9;
    for (std::size_t n = 0; n < state.displacement.size(); ++n) {
      state.displacement[n] = (f - Mat2::Identity()) * model.mesh.nodes[n];
    }
    for (Vec4& e : state.strain) e = Vec4(0.1, -0.1, 0.0, 0.2);
    const ElementQuality quality =
        evaluate_quality(model, state, current_coordinates(model, state));
    for (std::size_t e = 0; e < quality.jacobian_ratio.size(); ++e) {
      EXPECT_NEAR(quality.jacobian_ratio[e], 0.99, 1e-14);
      EXPECT_NEAR(quality.volume[e], 0.99 * model.volume_reference[e], 1e-14);
      EXPECT_NEAR(quality.eps_q[e], std::sqrt(0.08 / 3.0), 1e-15);
    }
  }
}

TEST(MeshQuality, AveragesAreOverDeformedElementsOnlyAndNaNWithoutThem) {
  ElementQuality quality;
  quality.jacobian_ratio = {1.0, 0.9, 0.5, -0.2};
  quality.eps_q = {0.01, 0.05, 0.25, 0.02};
  quality.yielded = {0, 1, 1, 0};
  const QualitySummary summary = summarise(quality);
  EXPECT_EQ(summary.jacobian_ratio_min, -0.2);
  EXPECT_EQ(summary.n_elements_deformed, 2);
  EXPECT_NEAR(summary.jacobian_ratio_avg, 0.7, 1e-15);
  EXPECT_NEAR(summary.eps_q_avg, 0.15, 1e-15);
  EXPECT_EQ(summary.eps_q_max, 0.25);
  EXPECT_EQ(summary.n_elements_yielding, 2);
  EXPECT_FALSE(inside_recommended_zone(summary));  // J_avg 0.7 < 0.97

  quality.eps_q = {0.01, 0.02, 0.03, 0.0};  // 3 % is not above 3 %
  const QualitySummary undeformed = summarise(quality);
  EXPECT_TRUE(std::isnan(undeformed.jacobian_ratio_avg));
  EXPECT_TRUE(std::isnan(undeformed.eps_q_avg));
  EXPECT_TRUE(inside_recommended_zone(undeformed));
}

TEST(MeshQuality, RecommendedZoneBounds) {
  QualitySummary s;
  s.n_elements_deformed = 1;
  s.jacobian_ratio_avg = 0.97;
  s.eps_q_avg = 0.20;
  EXPECT_TRUE(inside_recommended_zone(s));
  s.jacobian_ratio_avg = 0.9699;
  EXPECT_FALSE(inside_recommended_zone(s));
  s.jacobian_ratio_avg = 0.98;
  s.eps_q_avg = 0.2001;
  EXPECT_FALSE(inside_recommended_zone(s));
  // The history rows decide the same way (NaN: inside).
  HistoryRow row;
  row.jacobian_ratio_avg = std::nan("");
  row.eps_q_avg = std::nan("");
  EXPECT_TRUE(row.inside_zone());
  row.jacobian_ratio_avg = 0.96;
  row.eps_q_avg = 0.1;
  EXPECT_FALSE(row.inside_zone());
}

TEST(Energies, KineticAndPotentialEnergyOfARigidMotion) {
  const FemModel model = block(ElementType::quad4_1gp);
  const FemState state = make_rest_state(model);
  const std::vector<Vec2> velocity(model.mesh.nodes.size(), Vec2(3.0, -4.0));
  const Energies e = compute_energies(model, model.reference, state, velocity, model.mesh.nodes);
  const double mass = 1700.0 * 8.0;
  EXPECT_NEAR(e.kinetic, 0.5 * mass * 25.0, 1e-9 * mass);
  EXPECT_NEAR(e.potential, mass * gravity_acceleration * 1.0, 1e-9 * mass);  // centroid at 1 m
  EXPECT_EQ(e.elastic, 0.0);
  EXPECT_NEAR(releasable_potential_energy(model), mass * gravity_acceleration * 1.0, 1e-9 * mass);
}

TEST(Energies, StoredElasticEnergyOfAUniaxialStress) {
  // σxx = s alone: W = s²/(2E) per unit volume.
  const FemModel model = block(ElementType::quad4_2x2);
  FemState state = make_rest_state(model);
  for (Vec4& s : state.stress) s = Vec4(1e5, 0.0, 0.0, 0.0);
  const Energies e =
      compute_energies(model, model.reference, state, state.velocity, model.mesh.nodes);
  EXPECT_NEAR(e.elastic, 1e10 / (2.0 * 23.8e6) * 8.0, 1e-9);
}

}  // namespace
}  // namespace slide::fem
