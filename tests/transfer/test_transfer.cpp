// The transfer on FE checkpoints built in memory: the geostatic column of docs/method.md §7,
// exact conservation of mass and volume, exact reproduction of linear stress fields and
// rigid-body motion, the element baseline, determinism and the refusal of bad input.
#include <cmath>
#include <cstring>
#include <iostream>
#include <optional>

#include <gtest/gtest.h>

#include "common/base/error.hpp"
#include "tools/synthetic/fem_checkpoints.hpp"
#include "transfer/transfer.hpp"

namespace slide::transfer {
namespace {

using synthetic::BlockFields;
using synthetic::make_block;

constexpr double rho = 1700.0;
constexpr double nu = 0.23;
constexpr double column_height = 4.0;
const double rho_g_h = rho * gravity_acceleration * column_height;

/// geostatic-4x4: a 4 m × 4 m column of 0.25 m quads, one Gauss point each, carrying
/// the exact geostatic stress at its Gauss points.
FemCheckpoint geostatic_column() {
  BlockFields fields;
  fields.stress = synthetic::geostatic_stress(rho, nu, column_height);
  FemCheckpoint fem = make_block(16, 16, 4.0, column_height, ElementType::quad4_1gp, fields, rho);
  fem.header.time = 0.0;
  return fem;
}

struct GeostaticError {
  double interior = 0.0;  // particles at least one element (0.25 m) from the boundary
  double everywhere = 0.0;
};

GeostaticError geostatic_error(const Particles& particles) {
  GeostaticError error;
  for (std::size_t p = 0; p < particles.count(); ++p) {
    const Vec2& x = particles.coordinates[p];
    const double exact = -rho * gravity_acceleration * (column_height - x.y());
    const double e = std::abs(particles.stress[p][1] - exact) / rho_g_h;
    error.everywhere = std::max(error.everywhere, e);
    const double h = 0.25 - 1e-12;
    if (x.x() >= h && x.x() <= 4.0 - h && x.y() >= h && x.y() <= column_height - h) {
      error.interior = std::max(error.interior, e);
    }
  }
  return error;
}

TransferOptions with(StressInterpolation interpolation,
                     std::optional<RbfPolynomial> polynomial = std::nullopt) {
  TransferOptions options;
  options.stress_interpolation = interpolation;
  options.rbf_polynomial = polynomial;
  return options;
}

TEST(Transfer, GeostaticColumnWithThePlainMultiquadric) {
  const TransferResult result = transfer(geostatic_column(), with(StressInterpolation::rbf));
  ASSERT_EQ(result.particles.particles.count(), 256u * 16u);
  EXPECT_EQ(result.report.rbf_polynomial, "none");
  const GeostaticError error = geostatic_error(result.particles.particles);
  std::cout << "geostatic-4x4, rbf (plain multiquadric, c = " << result.report.rbf_shape
            << " m): max |σyy − σyy_exact| / ρgH = " << error.interior
            << " (≥ one element from the boundary), " << error.everywhere << " (everywhere)\n";
  RecordProperty("interior_error", std::to_string(error.interior));
  RecordProperty("max_error", std::to_string(error.everywhere));
  EXPECT_LT(error.interior, 0.005);
  EXPECT_LT(error.everywhere, 0.05);
  // The interpolant passes through the Gauss values.
  EXPECT_LT(result.report.residual_relative_max, 1e-8);
}

TEST(Transfer, GeostaticColumnWithTheLinearPolynomialIsExact) {
  for (auto interpolation : {StressInterpolation::rbf, StressInterpolation::rbf_local}) {
    const TransferResult result =
        transfer(geostatic_column(), with(interpolation, RbfPolynomial::linear));
    const GeostaticError error = geostatic_error(result.particles.particles);
    std::cout << "geostatic-4x4, " << to_string(interpolation)
              << " + linear: max error / ρgH = " << error.everywhere << "\n";
    EXPECT_LT(error.everywhere, 1e-6);
    // σxx = σzz = K0 σyy and σxy = 0 too.
    const double k0 = nu / (1.0 - nu);
    for (const Vec4& s : result.particles.particles.stress) {
      EXPECT_NEAR(s[0], k0 * s[1], 1e-6 * rho_g_h);
      EXPECT_NEAR(s[2], k0 * s[1], 1e-6 * rho_g_h);
      EXPECT_NEAR(s[3], 0.0, 1e-6 * rho_g_h);
    }
  }
}

GeostaticError stress_difference(const Particles& a, const Particles& b) {
  GeostaticError difference;
  for (std::size_t p = 0; p < a.count(); ++p) {
    const Vec2& x = a.coordinates[p];
    const double d = (a.stress[p] - b.stress[p]).cwiseAbs().maxCoeff() / rho_g_h;
    difference.everywhere = std::max(difference.everywhere, d);
    const double h = 0.25 - 1e-12;
    if (x.x() >= h && x.x() <= 4.0 - h && x.y() >= h && x.y() <= column_height - h) {
      difference.interior = std::max(difference.interior, d);
    }
  }
  return difference;
}

TEST(Transfer, RbfAndRbfLocalAgreeOnTheGeostaticColumn) {
  const FemCheckpoint fem = geostatic_column();
  auto compare = [&](std::optional<RbfPolynomial> dense_polynomial,
                     std::optional<RbfPolynomial> local_polynomial, const char* label) {
    const TransferResult dense = transfer(fem, with(StressInterpolation::rbf, dense_polynomial));
    const TransferResult local =
        transfer(fem, with(StressInterpolation::rbf_local, local_polynomial));
    EXPECT_EQ(local.report.rbf_neighbours, default_rbf_neighbours);
    const GeostaticError d =
        stress_difference(dense.particles.particles, local.particles.particles);
    std::cout << "geostatic-4x4, " << label
              << ": max |σ_rbf − σ_rbf-local| / ρgH = " << d.everywhere
              << " (≥ one element from the boundary: " << d.interior << ")\n";
    return d;
  };
  // With the same linear polynomial both are exact: they agree to round-off everywhere.
  EXPECT_LT(compare(RbfPolynomial::linear, RbfPolynomial::linear, "both linear").everywhere, 1e-9);
  // With their defaults (rbf: none, the paper's form; rbf-local: linear) they agree within
  // 1 % of ρgH away from the free boundaries; at the boundary particles the difference is
  // the plain multiquadric's own extrapolation error (< 5 %, see the test above), since
  // rbf-local + linear is exact there.
  const GeostaticError defaults = compare(std::nullopt, std::nullopt, "defaults (none vs linear)");
  EXPECT_LT(defaults.interior, 0.01);
  EXPECT_LT(defaults.everywhere, 0.05);
  // Both plain: the local multiquadric over 16 points reproduces a linear field poorly
  // (the reason rbf-local defaults to the linear polynomial); reported, not asserted.
  compare(RbfPolynomial::none, RbfPolynomial::none, "both none");
  // The same comparison on the column-short FE states: test_fem2mpm_cli.cpp.
}

TEST(Transfer, MassAndVolumeAreConservedExactlyForEveryElementAndLayout) {
  BlockFields fields;
  fields.displacement = synthetic::distortion(0.12);
  struct Case {
    ElementType type;
    std::vector<std::string> layouts;
  };
  const std::vector<Case> cases{
      {ElementType::quad4_1gp, {"1", "2x3", "4", "7x5", "10"}},
      {ElementType::quad4_2x2, {"1", "3", "4x2", "6"}},
      {ElementType::tri3, {"1", "3", "4", "6", "7", "12", "13", "16"}},
  };
  for (const auto& c : cases) {
    const FemCheckpoint fem = make_block(7, 5, 3.5, 2.0, c.type, fields, 1925.0);
    double fe_mass = 0.0, fe_volume = 0.0;
    for (Index e = 0; e < fem.mesh.element_count(); ++e) {
      fe_mass += 1925.0 * fem.volume_reference[static_cast<std::size_t>(e)];
      fe_volume += fem.volume[static_cast<std::size_t>(e)];
    }
    for (const auto& layout : c.layouts) {
      TransferOptions options = with(StressInterpolation::element);
      options.particles = parse_particles_per_element(layout, "test");
      const TransferResult result = transfer(fem, options);
      const Particles& particles = result.particles.particles;
      double mass = 0.0, volume = 0.0;
      for (std::size_t p = 0; p < particles.count(); ++p) {
        EXPECT_GT(particles.mass[p], 0.0);
        EXPECT_GT(particles.volume[p], 0.0);
        EXPECT_DOUBLE_EQ(particles.size[p].x(), std::sqrt(particles.volume[p]));
        mass += particles.mass[p];
        volume += particles.volume[p];
      }
      const std::string what = std::string(to_string(c.type)) + " " + layout;
      EXPECT_NEAR(mass, fe_mass, 1e-12 * fe_mass) << what;
      EXPECT_NEAR(volume, fe_volume, 1e-12 * fe_volume) << what;
      EXPECT_NEAR(result.report.mass_particles, result.report.mass_fe, 1e-12 * fe_mass) << what;
      EXPECT_NEAR(result.report.volume_particles, result.report.volume_fe, 1e-12 * fe_volume)
          << what;
      // The volume is the deformed one, the mass the undeformed one.
      EXPECT_GT(std::abs(fe_volume - 7.0), 1e-3) << what;
    }
  }
}

TEST(Transfer, LinearStressOnADistortedMeshIsReproducedWithTheLinearPolynomial) {
  // σ(x) = σ0 + x·a + y·b, every component linear, on a strongly distorted mesh.
  const Vec4 s0(-4.0e4, -9.0e4, -3.0e4, 5.0e3);
  const Vec4 a(1.5e4, -2.0e3, 4.0e3, -7.0e3);
  const Vec4 b(3.0e3, 1.7e4, 5.0e3, 2.0e3);
  auto linear = [=](const Vec2& x) -> Vec4 { return s0 + x.x() * a + x.y() * b; };
  BlockFields fields;
  fields.displacement = synthetic::distortion(0.15);
  fields.stress = linear;
  for (auto type : {ElementType::quad4_1gp, ElementType::quad4_2x2, ElementType::tri3}) {
    const FemCheckpoint fem = make_block(10, 6, 5.0, 3.0, type, fields);
    double scale = 0.0;
    for (const Vec4& s : fem.stress) scale = std::max(scale, s.cwiseAbs().maxCoeff());
    for (auto interpolation : {StressInterpolation::rbf, StressInterpolation::rbf_local}) {
      for (auto polynomial : {RbfPolynomial::linear, RbfPolynomial::none}) {
        const TransferResult result = transfer(fem, with(interpolation, polynomial));
        const Particles& particles = result.particles.particles;
        double error = 0.0;
        for (std::size_t p = 0; p < particles.count(); ++p) {
          error = std::max(
              error,
              (particles.stress[p] - linear(particles.coordinates[p])).cwiseAbs().maxCoeff());
        }
        std::cout << "linear stress, distorted " << to_string(type) << ", "
                  << to_string(interpolation) << " + " << to_string(polynomial)
                  << ": max relative error at the particles " << error / scale << "\n";
        if (polynomial == RbfPolynomial::linear) {
          EXPECT_LT(error, 1e-9 * scale) << to_string(type) << " " << to_string(interpolation);
        }
      }
    }
  }
}

TEST(Transfer, CollapsedElementsGiveNoRbfCentre) {
  // A linear stress field over a 6 × 5 block whose second row of cells has been squashed
  // to 5 % of its height (everything above it dropped by 0.95 h). The squashed elements'
  // Gauss points carry a meaningless stress (a collapsed element's strain is), ±20 % of
  // the field's scale. With the default ratio they are no RBF centres, so with the linear
  // polynomial every particle, those of the squashed row included, gets the linear field
  // back exactly; with the ratio at 0 (only inverted elements excluded) they do not.
  const Vec4 s0(-4.0e4, -9.0e4, -3.0e4, 5.0e3);
  const Vec4 a(1.5e4, -2.0e3, 4.0e3, -7.0e3);
  const Vec4 b(3.0e3, 1.7e4, 5.0e3, 2.0e3);
  auto linear = [=](const Vec2& x) -> Vec4 { return s0 + x.x() * a + x.y() * b; };
  const double h = 0.6;  // cell height of the 3 m high block
  BlockFields fields;
  fields.displacement = [h](const Vec2& X) { return Vec2(0.0, X.y() > 1.5 * h ? -0.95 * h : 0.0); };
  fields.stress = linear;
  for (auto type : {ElementType::quad4_1gp, ElementType::quad4_2x2, ElementType::tri3}) {
    FemCheckpoint fem = make_block(6, 5, 4.0, 3.0, type, fields);
    double scale = 0.0;
    for (const Vec4& s : fem.stress) scale = std::max(scale, s.cwiseAbs().maxCoeff());
    std::size_t squashed_points = 0;
    for (std::size_t g = 0; g < fem.stress.size(); ++g) {
      const auto e = static_cast<std::size_t>(fem.gauss_element[g]);
      if (fem.volume[e] > 0.1 * fem.volume_reference[e]) continue;
      fem.stress[g] += Vec4::Constant((g % 2 == 0 ? 0.2 : -0.2) * scale);
      ++squashed_points;
    }
    const std::size_t squashed_elements = type == ElementType::tri3 ? 12U : 6U;
    ASSERT_EQ(squashed_points, squashed_elements * (type == ElementType::quad4_2x2 ? 4U : 1U));

    for (auto interpolation : {StressInterpolation::rbf, StressInterpolation::rbf_local}) {
      const std::string label =
          std::string(to_string(type)) + " " + std::string(to_string(interpolation));
      auto max_error = [&](const TransferResult& result) {
        const Particles& particles = result.particles.particles;
        double error = 0.0;
        for (std::size_t p = 0; p < particles.count(); ++p) {
          error = std::max(
              error,
              (particles.stress[p] - linear(particles.coordinates[p])).cwiseAbs().maxCoeff());
        }
        return error / scale;
      };
      TransferOptions options = with(interpolation, RbfPolynomial::linear);
      const TransferResult excluded = transfer(fem, options);
      EXPECT_EQ(excluded.report.collapsed_elements, squashed_elements) << label;
      EXPECT_EQ(excluded.report.excluded_gauss_points, squashed_points) << label;
      EXPECT_DOUBLE_EQ(excluded.report.collapsed_volume_ratio, default_collapsed_volume_ratio);
      EXPECT_LT(max_error(excluded), 1e-9) << label;
      // Mass and volume are not the centres' business: every element keeps its particles.
      EXPECT_NEAR(excluded.report.mass_particles, excluded.report.mass_fe,
                  1e-12 * excluded.report.mass_fe);
      EXPECT_NEAR(excluded.report.volume_particles, excluded.report.volume_fe,
                  1e-12 * excluded.report.volume_fe);

      options.collapsed_volume_ratio = 0.0;
      const TransferResult kept = transfer(fem, options);
      EXPECT_EQ(kept.report.collapsed_elements, 0U) << label;
      EXPECT_EQ(kept.report.excluded_gauss_points, 0U) << label;
      EXPECT_GT(max_error(kept), 0.01) << label;
    }
  }
}

TEST(Transfer, EveryElementCollapsedIsAnErrorForTheRbfsOnly) {
  FemCheckpoint fem = make_block(2, 2, 1.0, 1.0, ElementType::quad4_1gp);
  for (double& v : fem.volume) v *= 0.1;  // the checkpoint says: 10 % of V_0 is left
  try {
    (void)transfer(fem, with(StressInterpolation::rbf_local));
    FAIL() << "expected an Error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("all 4 elements have collapsed"), std::string::npos)
        << e.what();
  }
  EXPECT_EQ(transfer(fem, with(StressInterpolation::element)).report.collapsed_elements, 4U);
  TransferOptions options = with(StressInterpolation::rbf);
  options.collapsed_volume_ratio = 1.5;
  EXPECT_THROW((void)transfer(fem, options), Error);
}

TEST(Transfer, RigidBodyVelocityIsReproducedExactly) {
  const Vec2 v0(1.3, -0.4), centre(1.0, 0.5);
  const double omega = 0.35;  // rad/s
  auto rigid = [=](const Vec2& x) -> Vec2 {
    return v0 + omega * Vec2(-(x.y() - centre.y()), x.x() - centre.x());
  };
  BlockFields fields;
  fields.displacement = synthetic::distortion(0.1);
  fields.velocity = rigid;
  for (auto type : {ElementType::quad4_1gp, ElementType::tri3}) {
    const FemCheckpoint fem = make_block(6, 4, 3.0, 2.0, type, fields);
    const TransferResult result = transfer(fem, with(StressInterpolation::element));
    const Particles& particles = result.particles.particles;
    for (std::size_t p = 0; p < particles.count(); ++p) {
      EXPECT_LT((particles.velocity[p] - rigid(particles.coordinates[p])).norm(), 1e-14);
    }
    // Linear momentum of a rigid motion: every measure agrees (the layouts integrate
    // linear fields exactly, and so does any lumping).
    const TransferReport& r = result.report;
    EXPECT_LT((r.momentum_particles - r.momentum_fe_element).norm(),
              1e-12 * r.momentum_particles.norm());
    EXPECT_LT((r.momentum_particles - r.momentum_fe_nodal).norm(),
              1e-12 * r.momentum_particles.norm());
  }
}

TEST(Transfer, ParticlesSitInsideTheirDeformedElementWithNodalFieldsByShapeFunctions) {
  BlockFields fields;
  fields.displacement = synthetic::distortion(0.12);
  fields.velocity = [](const Vec2& x) { return Vec2(x.x() * x.y(), -x.x()); };
  const FemCheckpoint fem = make_block(4, 3, 2.0, 1.5, ElementType::quad4_2x2, fields);
  const TransferResult result = transfer(fem, with(StressInterpolation::element));
  const Particles& particles = result.particles.particles;
  const ParticleLayout layout = quad_layout(4, 4);
  for (std::size_t p = 0; p < particles.count(); ++p) {
    const Index e = particles.element[p];
    const auto& point = layout.points[p % 16];
    const ElementNodes x = fem.mesh.element_nodes(e, fem.coordinates);
    const ElementNodes X = fem.mesh.element_nodes(e, fem.mesh.nodes);
    EXPECT_LT((particles.coordinates[p] - map_to_physical(ElementShape::quad4, x, point.xi)).norm(),
              1e-14);
    EXPECT_LT((particles.displacement[p] - (map_to_physical(ElementShape::quad4, x, point.xi) -
                                            map_to_physical(ElementShape::quad4, X, point.xi)))
                  .norm(),
              1e-14);
    EXPECT_EQ(particles.id[p], static_cast<std::int64_t>(p));
    EXPECT_EQ(particles.material_id[p], 0);
  }
}

TEST(Transfer, ElementBaselineCopiesTheNearestGaussPointOfTheOwningElement) {
  BlockFields fields;
  fields.displacement = synthetic::distortion(0.1);
  fields.stress = [](const Vec2& x) { return Vec4(x.x(), x.y(), x.x() * x.y(), 1.0); };
  fields.state = [](const Vec2& x) { return MaterialState{0.01 * x.x(), -0.002 * x.y()}; };
  fields.strain = [](const Vec2& x) { return Vec4(1e-3 * x.x(), -2e-3 * x.y(), 0.0, 5e-4); };
  for (auto type : {ElementType::quad4_1gp, ElementType::quad4_2x2, ElementType::tri3}) {
    const FemCheckpoint fem = make_block(3, 3, 3.0, 3.0, type, fields);
    const TransferResult result = transfer(fem, with(StressInterpolation::element));
    const Particles& particles = result.particles.particles;
    const std::size_t gp_per_element = quadrature_rule(type).size();
    const ParticleLayout layout = make_layout(shape_of(type), ParticlesPerElement{});
    for (std::size_t p = 0; p < particles.count(); ++p) {
      const auto e = static_cast<std::size_t>(particles.element[p]);
      const Vec2& xi = layout.points[p % static_cast<std::size_t>(layout.count())].xi;
      // For 2×2 elements: the Gauss point in the particle's quadrant.
      std::size_t g = e * gp_per_element;
      if (type == ElementType::quad4_2x2) {
        const bool right = xi.x() > 0.0, top = xi.y() > 0.0;
        g += top ? (right ? 2 : 3) : (right ? 1 : 0);
      }
      EXPECT_EQ(particles.stress[p], fem.stress[g]);
      EXPECT_EQ(particles.strain[p], fem.strain[g]);
      EXPECT_EQ(particles.state[p].plastic_shear_strain,
                fem.material_state[g].plastic_shear_strain);
      EXPECT_EQ(particles.state[p].plastic_volumetric_strain,
                fem.material_state[g].plastic_volumetric_strain);
      EXPECT_DOUBLE_EQ(particles.eps_q[p], deviatoric_strain(fem.strain[g]));
    }
  }
}

TEST(Transfer, FillsTheParticleFileHeaderAndSettings) {
  BlockFields fields;
  fields.stress = synthetic::geostatic_stress(rho, nu, 2.0);
  const FemCheckpoint fem = make_block(4, 4, 2.0, 2.0, ElementType::quad4_1gp, fields);
  TransferOptions options = with(StressInterpolation::rbf_local);
  options.particles = parse_particles_per_element("3x2", "test");
  options.rbf_neighbours = 9;
  options.rbf_shape = 0.3;
  const TransferResult result = transfer(fem, options);
  const ParticleCheckpoint& out = result.particles;
  EXPECT_EQ(out.header.kind, CheckpointKind::particles);
  EXPECT_EQ(out.header.time, fem.header.time);
  EXPECT_EQ(out.header.step, fem.header.step);
  EXPECT_EQ(out.header.case_name, fem.header.case_name);
  EXPECT_EQ(out.header.pe0, fem.header.pe0);
  EXPECT_EQ(out.materials.size(), 1u);
  EXPECT_EQ(out.materials[0].name, "soil");
  EXPECT_EQ(out.transfer.transfer_time, fem.header.time);
  EXPECT_EQ(out.transfer.particles_per_element, "3x2");
  EXPECT_EQ(out.transfer.stress_interpolation, "rbf-local");
  EXPECT_EQ(out.transfer.rbf_polynomial, "linear");
  EXPECT_EQ(out.transfer.rbf_shape, 0.3);
  EXPECT_EQ(out.transfer.rbf_neighbours, 9);
  EXPECT_EQ(out.particles.count(), 16u * 6u);
  out.particles.check_consistent_sizes();
}

TEST(Transfer, IsDeterministic) {
  BlockFields fields;
  fields.displacement = synthetic::distortion(0.1);
  fields.stress = [](const Vec2& x) {
    return Vec4(std::sin(x.x()), std::cos(x.y()), x.x(), x.y());
  };
  const FemCheckpoint fem = make_block(12, 9, 3.0, 2.0, ElementType::quad4_2x2, fields);
  for (auto interpolation : {StressInterpolation::rbf, StressInterpolation::rbf_local}) {
    const Particles a = transfer(fem, with(interpolation)).particles.particles;
    const Particles b = transfer(fem, with(interpolation)).particles.particles;
    ASSERT_EQ(a.count(), b.count());
    EXPECT_EQ(std::memcmp(a.stress.data(), b.stress.data(), a.count() * sizeof(Vec4)), 0);
    EXPECT_EQ(std::memcmp(a.coordinates.data(), b.coordinates.data(), a.count() * sizeof(Vec2)), 0);
    EXPECT_EQ(std::memcmp(a.mass.data(), b.mass.data(), a.count() * sizeof(double)), 0);
  }
}

TEST(Transfer, CountsInvertedElementsAsFemSolveDoesWhateverTheParticleLayout) {
  // The centre cell's top-right node pushed in to a quarter of the cell: a re-entrant
  // element whose centre det J (1/16) and area (0.25 m²) are positive but whose corner
  // folds. The particle points of a 1 × 1 layout are the centre only, so checking det J
  // there (the transfer's test before is_inverted) let it through; the corners do not.
  FemCheckpoint fem = make_block(3, 3, 3.0, 3.0, ElementType::quad4_1gp);
  const auto top_right = static_cast<std::size_t>(fem.mesh.element(4)[2]);
  fem.coordinates[top_right] = Vec2(1.25, 1.25);
  fem.displacement[top_right] = fem.coordinates[top_right] - fem.mesh.nodes[top_right];
  for (Index e = 0; e < fem.mesh.element_count(); ++e) {
    fem.volume[static_cast<std::size_t>(e)] =
        element_area(ElementShape::quad4, fem.mesh.element_nodes(e, fem.coordinates));
  }
  ASSERT_GT(fem.volume[4], 0.0);
  for (const ParticlesPerElement layout : {ParticlesPerElement{1, 1}, ParticlesPerElement{}}) {
    TransferOptions options = with(StressInterpolation::element);
    options.particles = layout;
    try {
      (void)transfer(fem, options);
      ADD_FAILURE() << layout.nx << "x" << layout.ny << ": expected an Error";
    } catch (const Error& e) {
      const std::string message = e.what();
      EXPECT_NE(message.find("element 4 is inverted"), std::string::npos) << message;
      EXPECT_NE(message.find("corner ξ = (1, 1)"), std::string::npos) << message;
    }
    options.allow_inverted = true;
    EXPECT_EQ(transfer(fem, options).report.inverted_elements, std::vector<Index>{4});
  }
}

TEST(Transfer, RefusesAVolumeTheGeometryContradicts) {
  FemCheckpoint fem = make_block(2, 2, 2.0, 2.0, ElementType::tri3);
  fem.volume[3] = -fem.volume[3];  // the nodes are those of the undeformed block
  try {
    (void)transfer(fem, with(StressInterpolation::element));
    FAIL() << "expected an Error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("/elements/volume of element 3"), std::string::npos)
        << e.what();
  }
}

TEST(Transfer, RefusesAnInvertedElementNamingItUnlessAllowed) {
  FemCheckpoint fem = make_block(3, 3, 3.0, 3.0, ElementType::quad4_1gp);
  // Push the top-right node of element 4 (the centre cell) through its bottom-left node.
  const auto nodes = fem.mesh.element(4);
  const auto top_right = static_cast<std::size_t>(nodes[2]);
  fem.coordinates[top_right] = Vec2(0.5, 0.5);
  fem.displacement[top_right] = fem.coordinates[top_right] - fem.mesh.nodes[top_right];
  for (Index e = 0; e < fem.mesh.element_count(); ++e) {
    fem.volume[static_cast<std::size_t>(e)] =
        element_area(ElementShape::quad4, fem.mesh.element_nodes(e, fem.coordinates));
  }
  try {
    (void)transfer(fem, with(StressInterpolation::element));
    FAIL() << "expected an Error";
  } catch (const Error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("element 4 is inverted"), std::string::npos) << message;
    EXPECT_NE(message.find("--allow-inverted"), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
  TransferOptions options = with(StressInterpolation::element);
  options.allow_inverted = true;
  const TransferResult result = transfer(fem, options);
  ASSERT_FALSE(result.report.inverted_elements.empty());
  EXPECT_EQ(result.report.inverted_elements.front(), 4);
  const Particles& particles = result.particles.particles;
  for (std::size_t p = 0; p < particles.count(); ++p) EXPECT_GT(particles.volume[p], 0.0);
  EXPECT_NEAR(result.report.mass_particles, result.report.mass_fe, 1e-12 * result.report.mass_fe);
}

TEST(Transfer, RefusesNonFiniteFieldsNamingTheDataset) {
  FemCheckpoint fem = make_block(2, 2, 1.0, 1.0, ElementType::quad4_1gp);
  fem.stress[3][1] = std::nan("");
  try {
    (void)transfer(fem, with(StressInterpolation::rbf));
    FAIL() << "expected an Error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("/gauss_points/stress entry 3"), std::string::npos)
        << e.what();
  }
}

TEST(Transfer, RefusesADenseSystemThatDoesNotFit) {
  TransferOptions options = with(StressInterpolation::rbf);
  options.dense_memory_limit = 1000;
  try {
    (void)transfer(geostatic_column(), options);
    FAIL() << "expected an Error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("use --stress-interpolation rbf-local"), std::string::npos)
        << e.what();
  }
}

TEST(Transfer, CaseFileSettingsBecomeOptions) {
  TransferSpec spec;
  spec.particles_x = 3;
  spec.particles_y = 5;
  spec.particles_triangle = 7;
  spec.stress_interpolation = StressInterpolation::rbf_local;
  spec.rbf_shape = 0.4;
  spec.rbf_neighbours = 12;
  const TransferOptions options = options_from(spec);
  EXPECT_EQ(options.particles.nx, 3);
  EXPECT_EQ(options.particles.ny, 5);
  EXPECT_EQ(options.particles.triangle, 7);
  EXPECT_EQ(effective_polynomial(options), RbfPolynomial::linear);
  EXPECT_EQ(effective_polynomial(with(StressInterpolation::rbf)), RbfPolynomial::none);
  EXPECT_EQ(options.rbf_shape, 0.4);
  EXPECT_EQ(options.rbf_neighbours, 12);
}

TEST(TransferReport, JsonNameAndContent) {
  EXPECT_EQ(report_path("out/tt2/particles.h5"),
            std::filesystem::path("out/tt2/particles.transfer.json"));
  EXPECT_EQ(report_path("p"), std::filesystem::path("p.transfer.json"));
  const TransferResult result = transfer(geostatic_column(), with(StressInterpolation::rbf_local));
  const std::string json = report_json(result.report);
  for (const char* key : {"\"particles\": 4096", "\"mass_fe\"", "\"kinetic_energy_fe_nodal\"",
                          "\"condition_estimate\"", "\"residual_stress_rms\"", "\"rbf_shape\""}) {
    EXPECT_NE(json.find(key), std::string::npos) << key << "\n" << json;
  }
  EXPECT_FALSE(format_report_lines(result.report).empty());
}

}  // namespace
}  // namespace slide::transfer

namespace slide::transfer {
namespace {

/// The geostatic column with the multi-yield soil in FE: a frozen strength and two
/// surfaces per Gauss point, each value distinct (a function of the Gauss point).
FemCheckpoint multi_yield_column(std::optional<MaterialModel> mpm_model) {
  FemCheckpoint fem = geostatic_column();
  for (Material& m : fem.materials) {
    m.model = MaterialModel::pressure_independent_multi_yield;
    m.yield_surfaces = 2;
    m.mpm_model = mpm_model;
  }
  fem.surface_stress.per_point = 2;
  fem.surface_stress.resize(fem.stress.size());
  for (std::size_t g = 0; g < fem.stress.size(); ++g) {
    fem.material_state[g].peak_strength = 1e5 + static_cast<double>(g);
    fem.surface_stress.values[2 * g] = Vec4(1.0, -2.0, 1.0, 3.0) * static_cast<double>(g);
    fem.surface_stress.values[2 * g + 1] = Vec4(-1.0, 0.5, 0.5, 2.0) * static_cast<double>(g);
  }
  return fem;
}

TEST(Transfer, MultiYieldStateTravelsWithTheElementWhenMpmRunsTheSameModel) {
  const FemCheckpoint fem = multi_yield_column(std::nullopt);
  const TransferResult result = transfer(fem, with(StressInterpolation::element));
  const Particles& p = result.particles.particles;
  ASSERT_EQ(p.surface_stress.per_point, 2u);
  for (std::size_t i = 0; i < p.count(); ++i) {
    const auto g = static_cast<std::size_t>(p.element[i]);  // one Gauss point per element
    EXPECT_EQ(p.state[i].peak_strength, fem.material_state[g].peak_strength) << i;
    EXPECT_EQ(p.surface_stress.values[2 * i], fem.surface_stress.values[2 * g]) << i;
    EXPECT_EQ(p.surface_stress.values[2 * i + 1], fem.surface_stress.values[2 * g + 1]) << i;
  }
}

TEST(Transfer, AnotherMpmModelStartsWithoutTheFeSurfaces) {
  const TransferResult result =
      transfer(multi_yield_column(MaterialModel::mohr_coulomb), with(StressInterpolation::element));
  const Particles& p = result.particles.particles;
  EXPECT_EQ(p.surface_stress.per_point, 0u);
  EXPECT_TRUE(p.surface_stress.values.empty());
  p.check_consistent_sizes();
}

}  // namespace
}  // namespace slide::transfer

namespace slide::transfer {
namespace {

// A saturated block on a distorted mesh (docs/method.md §10): nodal p linear in x and y,
// p_static linear too, σ′v0, p′₀ and r_u,max per Gauss point. The particles get p and Δp
// exactly (a linear field through the element's shape functions), the Gauss-point values
// of their source points, and the liquefied flag and S_r of the material's rule wherever
// their source point's r_u,max reaches 0.7.
TEST(Transfer, PorePressureAndLiquefactionStateReachTheParticles) {
  BlockFields fields;
  fields.displacement = synthetic::distortion(0.1);
  FemCheckpoint fem = make_block(8, 6, 4.0, 3.0, ElementType::quad4_2x2, fields, 2000.0);
  Material& m = fem.materials[0];
  m.porosity = 0.4;
  m.conductivity_x = m.conductivity_y = 1e-5;
  m.liquefaction.enabled = true;
  m.liquefaction.correlation = ResidualStrengthCorrelation::ratio;
  m.liquefaction.strength_ratio = 0.12;
  m.liquefaction.friction_angle = 30.0;
  auto pressure = [](const Vec2& x) { return 5e4 + 1.5e3 * x.x() - 9.81e3 * x.y(); };
  auto at_rest = [](const Vec2& x) { return 4e4 - 9.81e3 * x.y(); };
  fem.pore_pressure.clear();
  for (std::size_t n = 0; n < fem.coordinates.size(); ++n) {
    fem.pore_pressure.push_back(pressure(fem.coordinates[n]));
    fem.static_pore_pressure.push_back(at_rest(fem.coordinates[n]));
  }
  for (Index e = 0; e < fem.mesh.element_count(); ++e) {
    const ElementNodes x = fem.mesh.element_nodes(e, fem.coordinates);
    const Vec2 centre =
        map_to_physical(ElementShape::quad4, x, reference_centre(ElementShape::quad4));
    fem.element_pore_pressure.push_back(pressure(centre));
  }
  for (const Vec2& x : fem.gauss_coordinates) {
    fem.initial_vertical_effective_stress.push_back(1e5 * (4.0 - x.y()));
    fem.initial_mean_effective_stress.push_back(0.7e4 * (4.0 - x.y()));
    fem.max_pore_pressure_ratio.push_back(x.x() / 4.0);  // 0.7 at x = 2.8 m
  }
  const TransferResult result = transfer(fem, with(StressInterpolation::element));
  const Particles& q = result.particles.particles;
  ASSERT_EQ(q.liquefied.size(), q.count());
  const ParticleLayout layout = quad_layout(4, 4);
  std::size_t liquefied = 0;
  double area = 0.0;
  for (std::size_t p = 0; p < q.count(); ++p) {
    const Vec2& x = q.coordinates[p];
    EXPECT_NEAR(q.pore_pressure[p], pressure(x), 1e-9 * 5e4) << p;
    EXPECT_NEAR(q.excess_pore_pressure[p], pressure(x) - at_rest(x), 1e-9 * 5e4) << p;
    // The source: the element's Gauss point nearest in reference coordinates.
    const Vec2 xi = layout.points[p % 16].xi;
    const auto e = static_cast<std::size_t>(q.element[p]);
    std::size_t g = 4 * e;
    for (std::size_t k = 4 * e; k < 4 * e + 4; ++k) {
      if ((fem.gauss_local_coordinates[k] - xi).norm() <
          (fem.gauss_local_coordinates[g] - xi).norm()) {
        g = k;
      }
    }
    const Vec2& xg = fem.gauss_coordinates[g];
    EXPECT_EQ(q.initial_vertical_effective_stress[p], 1e5 * (4.0 - xg.y())) << p;
    EXPECT_EQ(q.initial_mean_effective_stress[p], 0.7e4 * (4.0 - xg.y())) << p;
    EXPECT_EQ(q.max_pore_pressure_ratio[p], xg.x() / 4.0) << p;
    EXPECT_EQ(q.liquefied[p], xg.x() / 4.0 >= 0.7 ? 1 : 0) << p;
    if (q.liquefied[p] == 0) continue;
    ++liquefied;
    area += q.volume[p];
    EXPECT_NEAR(q.surface_stress.of(p)[0][1], 0.12 * 1e5 * (4.0 - xg.y()), 1e-8) << "S_r";
  }
  const PoreWaterReport& w = result.report.pore_water;
  EXPECT_GT(liquefied, 0u);
  EXPECT_LT(liquefied, q.count());
  EXPECT_EQ(w.capped_excess, 0u) << "Δp stays below σ′v0 everywhere";
  ASSERT_EQ(w.materials.size(), 1u);
  EXPECT_EQ(w.materials[0].liquefied, liquefied);
  EXPECT_NEAR(w.materials[0].liquefied_area, area, 1e-12);
  // ∫ p dA: the element p_e (the centre value) on V_t^e against Σ p_p V_p; equal for a
  // linear field on parallelograms, close on this distorted mesh.
  EXPECT_NEAR(w.pore_force_particles / w.pore_force_fe, 1.0, 1e-3);
}

}  // namespace
}  // namespace slide::transfer
