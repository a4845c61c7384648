// Mesh quality, the recommended transfer zone and the energies (docs/method.md §3).
#include <cmath>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <numbers>
#include <string>
#include <vector>

#include <fmt/ranges.h>
#include <gtest/gtest.h>

#include "fem/fem_model.hpp"
#include "fem/fem_output.hpp"
#include "fem/mesh_quality.hpp"
#include "fem/model_setup.hpp"
#include "tests/support/meshes.hpp"
#include "tools/synthetic/soil.hpp"

namespace slide::fem {
namespace {

FemModel block(ElementType type) {
  return make_model(testing::rectangle_mesh(type, 4, 2, 4.0, 2.0), {synthetic::soil()},
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
      EXPECT_NEAR(quality.volume[e], 0.99 * model.elements.volume_reference[e], 1e-14);
      EXPECT_NEAR(quality.eps_q[e], std::sqrt(0.08 / 3.0), 1e-15);
    }
  }
}

TEST(MeshQuality, AveragesAreOverDeformedElementsOnlyAndNaNWithoutThem) {
  ElementQuality quality;
  quality.jacobian_ratio = {1.0, 0.9, 0.5, -0.2};
  quality.scaled_jacobian = {1.0, 0.8, 0.4, -0.3};
  quality.volume = {1.0, 0.9, 0.5, -0.2};
  quality.volume_reference_total = 4.0;
  quality.eps_q = {0.01, 0.05, 0.25, 0.02};
  quality.yielded = {0, 1, 1, 0};
  quality.inverted = {0, 0, 0, 1};
  const QualitySummary summary = summarise(quality);
  EXPECT_EQ(summary.jacobian_ratio_min, -0.2);
  EXPECT_EQ(summary.n_elements_deformed, 2);
  EXPECT_NEAR(summary.jacobian_ratio_avg, 0.7, 1e-15);
  EXPECT_NEAR(summary.eps_q_avg, 0.15, 1e-15);
  EXPECT_EQ(summary.eps_q_max, 0.25);
  EXPECT_EQ(summary.n_elements_yielding, 2);
  EXPECT_FALSE(inside_recommended_zone(summary));  // J_avg 0.7 < 0.97
  // Σ V_t / Σ V_0 = (1 + 0.9 + 0.5 − 0.2)/4: the folded element's area counts negative.
  EXPECT_NEAR(summary.area_ratio, 0.55, 1e-15);
  EXPECT_EQ(summary.scaled_jacobian_min, -0.3);
  EXPECT_NEAR(summary.scaled_jacobian_avg, 0.6, 1e-15);  // (0.8 + 0.4)/2
  EXPECT_EQ(summary.n_elements_inverted, 1);

  quality.eps_q = {0.01, 0.02, 0.03, 0.0};  // 3 % is not above 3 %
  const QualitySummary undeformed = summarise(quality);
  EXPECT_TRUE(std::isnan(undeformed.jacobian_ratio_avg));
  EXPECT_TRUE(std::isnan(undeformed.eps_q_avg));
  EXPECT_TRUE(std::isnan(undeformed.scaled_jacobian_avg));
  EXPECT_EQ(undeformed.scaled_jacobian_min, -0.3);  // over all elements, deformed or not
  EXPECT_TRUE(inside_recommended_zone(undeformed));
}

// ------------------------------------------------------------------ area and shape

/// The nodes of one element (rows beyond its node count unused).
ElementNodes element(std::initializer_list<Vec2> points) {
  ElementNodes x = ElementNodes::Zero();
  int k = 0;
  for (const Vec2& p : points) x.row(k++) = p.transpose();
  return x;
}

/// The block's nodes mapped by x = F X (a homogeneous deformation).
std::vector<Vec2> mapped(const FemModel& model, const Mat2& f) {
  std::vector<Vec2> x;
  for (const Vec2& node : model.mesh.nodes) x.push_back(f * node);
  return x;
}

Mat2 rotation(double theta) {
  Mat2 r;
  r << std::cos(theta), -std::sin(theta), std::sin(theta), std::cos(theta);
  return r;
}

TEST(ScaledJacobian, OneForTheSquareAndTheEquilateralTriangle) {
  const ElementNodes square = element({{0, 0}, {2, 0}, {2, 2}, {0, 2}});
  EXPECT_EQ(scaled_jacobian(ElementShape::quad4, square), 1.0);
  // Shape only, not size or stretch: a 10 : 1 rectangle is as good as the square.
  EXPECT_EQ(scaled_jacobian(ElementShape::quad4, element({{0, 0}, {10, 0}, {10, 1}, {0, 1}})), 1.0);
  const ElementNodes equilateral = element({{0, 0}, {1, 0}, {0.5, std::sqrt(3.0) / 2}});
  EXPECT_NEAR(scaled_jacobian(ElementShape::tri3, equilateral), 1.0, 1e-15);
  // The right isosceles triangle: its 45° corners give sin 45°/sin 60° = sqrt(2/3).
  EXPECT_NEAR(scaled_jacobian(ElementShape::tri3, element({{0, 0}, {1, 0}, {0, 1}})),
              std::sqrt(2.0 / 3.0), 1e-15);
  // det J at the worst corner: det[e1 e2]/4 for the quad (half edges), det[e1 e2] for tri3.
  EXPECT_EQ(worst_corner(ElementShape::quad4, square).det_jacobian,
            jacobian(ElementShape::quad4, square, Vec2(-1, -1)).determinant());
  EXPECT_NEAR(worst_corner(ElementShape::tri3, equilateral).det_jacobian,
              jacobian(ElementShape::tri3, equilateral, Vec2(0, 0)).determinant(), 1e-15);

  // Every element of the undeformed blocks.
  for (const auto type : {ElementType::quad4_1gp, ElementType::quad4_2x2, ElementType::tri3}) {
    const FemModel model = block(type);
    const ElementQuality quality =
        evaluate_quality(model, make_rest_state(model), model.mesh.nodes);
    const double expected = type == ElementType::tri3 ? std::sqrt(2.0 / 3.0) : 1.0;
    for (const double s : quality.scaled_jacobian) EXPECT_NEAR(s, expected, 1e-15);
    EXPECT_EQ(summarise(quality).area_ratio, 1.0);
  }
}

TEST(ScaledJacobian, AParallelogramShearedByThetaGivesCosThetaAtEveryCorner) {
  // Simple shear x = X + tan θ Y tilts the vertical edges by θ: the corner angles are
  // 90° ∓ θ, whose sine is cos θ at all four. The shear is isochoric (det F = 1), so
  // |J_t|/|J_0| stays 1 and the area ratio 1: only the scaled Jacobian sees it.
  for (const double degrees : {10.0, 30.0, 45.0, 60.0, 80.0}) {
    const double theta = degrees * std::numbers::pi / 180.0;
    const ElementNodes x =
        element({{0, 0}, {1, 0}, {1 + std::tan(theta), 1}, {std::tan(theta), 1}});
    for (int k = 0; k < 4; ++k) {
      const CornerJacobian corner = corner_jacobian(ElementShape::quad4, x, k);
      EXPECT_NEAR(corner.scaled_jacobian, std::cos(theta), 1e-15) << degrees << "°, corner " << k;
      // det J of the isoparametric map at that corner: the same sign, a quarter of det[e1 e2].
      const Vec2 xi = reference_corners(ElementShape::quad4)[static_cast<std::size_t>(k)];
      EXPECT_NEAR(corner.det_jacobian, jacobian(ElementShape::quad4, x, xi).determinant(), 1e-15);
    }
    Mat2 f;
    f << 1.0, std::tan(theta), 0.0, 1.0;
    const FemModel model = block(ElementType::quad4_1gp);
    const ElementQuality quality =
        evaluate_quality(model, make_rest_state(model), mapped(model, f));
    for (std::size_t e = 0; e < quality.scaled_jacobian.size(); ++e) {
      EXPECT_NEAR(quality.scaled_jacobian[e], std::cos(theta), 1e-14) << degrees << "°";
      EXPECT_NEAR(quality.jacobian_ratio[e], 1.0, 1e-14) << degrees << "°";
    }
    EXPECT_NEAR(summarise(quality).area_ratio, 1.0, 1e-14) << degrees << "°";
  }
}

TEST(AreaRatio, ARotatedMeshKeepsItsAreaOnUpdatedLagrangianCoordinates) {
  // Updated-Lagrangian kinematics carry the current geometry itself: after a rigid
  // rotation the nodes are at x = R X, and Σ V_t / Σ V_0 = det R = 1, the shape as well.
  for (const auto type : {ElementType::quad4_1gp, ElementType::quad4_2x2, ElementType::tri3}) {
    const FemModel model = block(type);
    const ElementQuality at_rest =
        evaluate_quality(model, make_rest_state(model), model.mesh.nodes);
    for (const double degrees : {30.0, 90.0, 150.0}) {
      const double theta = degrees * std::numbers::pi / 180.0;
      const ElementQuality quality =
          evaluate_quality(model, make_rest_state(model), mapped(model, rotation(theta)));
      const QualitySummary summary = summarise(quality);
      EXPECT_NEAR(summary.area_ratio, 1.0, 1e-14) << degrees << "°";
      EXPECT_NEAR(summary.jacobian_ratio_min, 1.0, 1e-14) << degrees << "°";
      EXPECT_EQ(summary.n_elements_inverted, 0);
      for (std::size_t e = 0; e < quality.scaled_jacobian.size(); ++e) {
        EXPECT_NEAR(quality.scaled_jacobian[e], at_rest.scaled_jacobian[e], 1e-14);
      }
    }
  }
}

TEST(AreaRatio, TheFormulaGivesOneForARigidRotationOfTheDisplacements) {
  // x = X + u with u = (R − I) X is the rotated mesh again: the area ratio is 1 to
  // round-off at any angle. This checks the formula Σ V_t / Σ V_0 on x = X + u, not the
  // small-strain kinematics (which do not produce this u: their rotation is linearised).
  // The linearised rotation u = θ (−Y, X) is a map with det F = 1 + θ², and the ratio says so.
  for (const auto type : {ElementType::quad4_1gp, ElementType::quad4_2x2, ElementType::tri3}) {
    const FemModel model = block(type);
    for (const double degrees : {5.0, 45.0, 120.0}) {
      const double theta = degrees * std::numbers::pi / 180.0;
      FemState state = make_rest_state(model);
      for (std::size_t n = 0; n < state.displacement.size(); ++n) {
        state.displacement[n] = (rotation(theta) - Mat2::Identity()) * model.mesh.nodes[n];
      }
      QualitySummary summary =
          summarise(evaluate_quality(model, state, current_coordinates(model, state)));
      EXPECT_NEAR(summary.area_ratio, 1.0, 1e-14) << degrees << "°";

      for (std::size_t n = 0; n < state.displacement.size(); ++n) {
        const Vec2& node = model.mesh.nodes[n];
        state.displacement[n] = theta * Vec2(-node.y(), node.x());
      }
      summary = summarise(evaluate_quality(model, state, current_coordinates(model, state)));
      EXPECT_NEAR(summary.area_ratio / (1.0 + theta * theta), 1.0, 1e-14) << degrees << "°";
    }
  }
}

TEST(Inverted, AFoldedElementIsNegativeAndCountedInvertedByTheSharedDefinition) {
  // The unit square with its third node pushed in to (0.25, 0.25): a re-entrant (arrow)
  // quad. Its corner 2 folds, det[e1 e2] = (−0.25, 0.75) × (0.75, −0.25) = −0.5 with
  // |e1| = |e2| = sqrt(0.625): scaled Jacobian −0.8. Yet det J at the centre is
  // Σ_k det[e1 e2]_k / 16 = (1 + 0.25 − 0.5 + 0.25)/16 > 0 and the area 0.25 > 0, so
  // |J_t|/|J_0| = 0.25 and V_t alone would pass it: the corners are what catch it.
  const ElementNodes arrow = element({{0, 0}, {1, 0}, {0.25, 0.25}, {0, 1}});
  const CornerJacobian worst = worst_corner(ElementShape::quad4, arrow);
  EXPECT_EQ(worst.corner, 2);
  EXPECT_NEAR(worst.scaled_jacobian, -0.8, 1e-15);
  EXPECT_NEAR(worst.det_jacobian, -0.125, 1e-15);
  EXPECT_NEAR(jacobian(ElementShape::quad4, arrow, Vec2(0, 0)).determinant(), 1.0 / 16.0, 1e-15);
  EXPECT_NEAR(element_area(ElementShape::quad4, arrow), 0.25, 1e-15);
  EXPECT_TRUE(is_inverted(ElementShape::quad4, arrow));
  // Fully folded (clockwise) and collapsed elements: −1, and 0 with zero area (inverted).
  EXPECT_EQ(scaled_jacobian(ElementShape::quad4, element({{0, 0}, {0, 1}, {1, 1}, {1, 0}})), -1.0);
  EXPECT_TRUE(is_inverted(ElementShape::tri3, element({{0, 0}, {0, 1}, {1, 0}})));
  const ElementNodes flat = element({{0, 0}, {1, 0}, {2, 0}});  // collinear
  EXPECT_EQ(scaled_jacobian(ElementShape::tri3, flat), 0.0);
  EXPECT_TRUE(is_inverted(ElementShape::tri3, flat));
  const ElementNodes collapsed_edge = element({{0, 0}, {1, 0}, {1, 0}, {0, 1}});  // |e| = 0
  EXPECT_EQ(scaled_jacobian(ElementShape::quad4, collapsed_edge), 0.0);
  // A quad with a zero-length edge is a triangle of positive area: degenerate corners,
  // det J > 0 inside, not inverted.
  EXPECT_FALSE(is_inverted(ElementShape::quad4, collapsed_edge));
  EXPECT_FALSE(is_inverted(ElementShape::quad4, element({{0, 0}, {1, 0}, {1, 1}, {0, 1}})));
  // One flat corner (the right face folded onto the base line) with a positive area:
  // degenerate (scaled Jacobian 0), not inverted; det J > 0 at its centre.
  const ElementNodes flat_corner = element({{0, 0}, {1, 0}, {2, 0}, {0, 1}});
  EXPECT_EQ(scaled_jacobian(ElementShape::quad4, flat_corner), 0.0);
  EXPECT_GT(jacobian(ElementShape::quad4, flat_corner, Vec2(0, 0)).determinant(), 0.0);
  EXPECT_FALSE(is_inverted(ElementShape::quad4, flat_corner));

  // In the mesh: push the top-right node of element 5 of the 4 × 2 block (cell (1, 1), nodes
  // 6, 7, 12, 11) down to a quarter of the cell. fem-solve's quality counts it inverted.
  const FemModel model = block(ElementType::quad4_1gp);
  FemState state = make_rest_state(model);
  const auto node = static_cast<std::size_t>(model.mesh.element(5)[2]);
  state.displacement[node] = Vec2(-0.75, -0.75);
  const ElementQuality quality = evaluate_quality(model, state, current_coordinates(model, state));
  EXPECT_NEAR(quality.scaled_jacobian[5], -0.8, 1e-15);
  EXPECT_NEAR(quality.jacobian_ratio[5], 0.25, 1e-15);
  EXPECT_EQ(quality.inverted[5], 1);
  const QualitySummary summary = summarise(quality);
  EXPECT_EQ(summary.n_elements_inverted, 1);  // its neighbour 6 keeps det J > 0
  EXPECT_NEAR(summary.scaled_jacobian_min, -0.8, 1e-15);
  EXPECT_GT(summary.jacobian_ratio_min, 0.0);  // what (|J_t|/|J_0|)_min alone misses
  HistoryRow row;
  row.jacobian_ratio_min = summary.jacobian_ratio_min;
  row.scaled_jacobian_min = summary.scaled_jacobian_min;
  EXPECT_TRUE(row.inverted());
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

TEST(History, RowsOfAHistoryWithoutTheShapeColumnsAreKeptOnRestart) {
  // A history fem-solve wrote before area_ratio and the scaled Jacobian: resume keeps its
  // rows up to the restart time with those columns NaN, and rewrites it with the new header.
  const std::filesystem::path path =
      std::filesystem::path(SLIDE_BINARY_DIR) / "tests" / "fem" / "old_fem_history.csv";
  std::filesystem::create_directories(path.parent_path());
  std::ofstream(path) << "time,kinetic_energy,pe0,ke_over_pe0,jacobian_ratio_min,"
                         "jacobian_ratio_avg,eps_q_avg,eps_q_max,n_elements_yielding\n"
                      << "0,0,100,0,1,nan,nan,0,5\n0.1,2,100,0.02,-0.5,0.9,0.04,0.1,3\n"
                      << "0.2,3,100,0.03,-0.6,0.8,0.05,0.2,2\n";
  FemHistory history(path, false);
  history.resume(0.1, Logger("test", true));
  ASSERT_EQ(history.rows().size(), 2U);
  EXPECT_EQ(history.rows()[1].n_elements_yielding, 3);
  EXPECT_TRUE(std::isnan(history.rows()[1].area_ratio));
  EXPECT_TRUE(std::isnan(history.rows()[1].scaled_jacobian_min));
  // Inversion as that history's run reported it: (|J_t|/|J_0|)_min < 0.
  EXPECT_TRUE(history.rows()[1].inverted());
  EXPECT_FALSE(history.rows()[0].inverted());
  HistoryRow row;
  row.time = 0.2;
  row.area_ratio = 0.97;
  row.scaled_jacobian_min = 0.5;
  row.scaled_jacobian_avg = std::nan("");
  history.add(row);
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, fmt::format("{}", fmt::join(history_columns, ",")));
  std::getline(in, line);
  std::getline(in, line);
  EXPECT_EQ(line, "0.1,2,100,0.02,-0.5,0.9,0.04,0.1,3,nan,nan,nan");
  std::getline(in, line);
  EXPECT_EQ(line, "0.2,0,0,0,1,0,0,0,0,0.97,0.5,nan");
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
