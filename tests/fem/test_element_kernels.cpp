// The element kernels: patch tests on distorted meshes, the rigid-body modes of the
// element stiffness, and the hourglass control of the one-point quad.
#include <fmt/format.h>
#include <gtest/gtest.h>

// Eigen's eigensolver, compiled for AVX-512 by GCC 12, trips a false
// -Wmaybe-uninitialized inside _mm512_extractf64x4_pd (GCC bug 105593, fixed in 13).
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <cmath>

#include <Eigen/Eigenvalues>

#include "fem/element_kernels.hpp"
#include "fem/fem_model.hpp"
#include "fem/model_setup.hpp"
#include "tests/support/eigen_checks.hpp"
#include "tests/support/meshes.hpp"
#include "tools/synthetic/soil.hpp"

namespace slide::fem {
namespace {

using synthetic::soil;
using testing::distort_interior;
using testing::max_abs;
using testing::rectangle_mesh;

const std::array<ElementType, 3> all_types{ElementType::quad4_1gp, ElementType::quad4_2x2,
                                           ElementType::tri3};

FemModel distorted_model(ElementType type) {
  Mesh mesh = rectangle_mesh(type, 4, 3, 4.0, 3.0);
  distort_interior(mesh, 1.0, 0.25);
  return make_model(std::move(mesh), {soil()}, Kinematics::small_strain, 1.0);
}

/// Sum of the element forces at every node (without gravity), with the stiffness
/// damping β_K = `rayleigh_stiffness` on the velocities of `state`.
std::vector<Vec2> assembled_forces(const FemModel& model, const FemState& state,
                                   double rayleigh_stiffness = 0.0) {
  std::vector<Vec2> element_force(model.mesh.connectivity.size());
  compute_element_forces(model, model.reference, state, element_force, rayleigh_stiffness);
  std::vector<Vec2> nodal(model.mesh.nodes.size(), Vec2::Zero());
  for (std::size_t slot = 0; slot < element_force.size(); ++slot) {
    nodal[static_cast<std::size_t>(model.mesh.connectivity[slot])] += element_force[slot];
  }
  return nodal;
}

TEST(PatchTest, EveryElementReproducesAConstantStrainExactlyOnADistortedMesh) {
  // u(x) = A x + c: a constant strain; with dt = 1 the "velocity" is the displacement.
  Mat2 a;
  a << 1.0e-3, -4.0e-4, 7.0e-4, -2.0e-3;
  const Vec2 c(0.3, -0.1);
  const Vec4 exact_strain(a(0, 0), a(1, 1), 0.0, a(0, 1) + a(1, 0));
  for (const auto type : all_types) {
    SCOPED_TRACE(to_string(type));
    const FemModel model = distorted_model(type);
    const std::vector<ConstitutiveModel> elastic{ConstitutiveModel::elastic(model.materials[0])};
    const Vec4 exact_stress = elastic[0].elastic_stress_increment(exact_strain);
    FemState state = make_rest_state(model);
    for (std::size_t n = 0; n < state.velocity.size(); ++n) {
      state.velocity[n] = a * model.mesh.nodes[n] + c;
    }
    update_stresses(model, model.reference, elastic, 1.0, false, state);
    const double scale = max_abs(exact_stress);
    for (std::size_t gp = 0; gp < state.stress.size(); ++gp) {
      EXPECT_LT(max_abs(state.strain[gp] - exact_strain), 1e-12 * 2e-3);
      EXPECT_LT(max_abs(state.stress[gp] - exact_stress), 1e-12 * scale);
    }
    // A constant stress is in equilibrium: the interior nodes feel no net force.
    const std::vector<Vec2> force = assembled_forces(model, state);
    const NodeSet* sets[] = {model.mesh.find_node_set("left"), model.mesh.find_node_set("right"),
                             model.mesh.find_node_set("base"), model.mesh.find_node_set("top")};
    for (std::size_t n = 0; n < force.size(); ++n) {
      bool boundary = false;
      for (const NodeSet* set : sets) {
        boundary = boundary || std::find(set->nodes.begin(), set->nodes.end(),
                                         static_cast<Index>(n)) != set->nodes.end();
      }
      if (!boundary) {
        EXPECT_LT(force[n].norm(), 1e-12 * scale) << "node " << n;
      }
    }
  }
}

int zero_eigenvalues(const ElementMatrix& k, int size) {
  const Eigen::MatrixXd block = k.topLeftCorner(size, size);
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> solver(block);
  const double largest = max_abs(solver.eigenvalues());
  int zeros = 0;
  for (Eigen::Index i = 0; i < solver.eigenvalues().size(); ++i) {
    if (std::abs(solver.eigenvalues()[i]) < 1e-10 * largest) ++zeros;
  }
  return zeros;
}

FemModel single_element(ElementType type, double hourglass_coefficient,
                        const std::vector<Vec2>& corners) {
  Mesh mesh;
  mesh.element_type = type;
  mesh.nodes = corners;
  for (std::size_t k = 0; k < corners.size(); ++k)
    mesh.connectivity.push_back(static_cast<Index>(k));
  mesh.material_id = {0};
  return make_model(std::move(mesh), {soil()}, Kinematics::small_strain, hourglass_coefficient);
}

const std::vector<Vec2> distorted_quad{{0.1, -0.2}, {2.3, 0.1}, {1.9, 1.7}, {-0.3, 1.2}};

TEST(ElementStiffness, StabilisedOnePointQuadHasOnlyTheThreeRigidBodyModes) {
  const FemModel model = single_element(ElementType::quad4_1gp, 1.0, distorted_quad);
  EXPECT_EQ(zero_eigenvalues(element_stiffness(model, model.reference, 0), 8), 3);
}

TEST(ElementStiffness, UnstabilisedOnePointQuadHasTwoSpuriousHourglassModes) {
  const FemModel model = single_element(ElementType::quad4_1gp, 0.0, distorted_quad);
  EXPECT_EQ(zero_eigenvalues(element_stiffness(model, model.reference, 0), 8), 5);
}

TEST(ElementStiffness, FullyIntegratedElementsHaveOnlyTheRigidBodyModes) {
  const FemModel quad = single_element(ElementType::quad4_2x2, 1.0, distorted_quad);
  EXPECT_EQ(zero_eigenvalues(element_stiffness(quad, quad.reference, 0), 8), 3);
  const FemModel tri =
      single_element(ElementType::tri3, 1.0, {{0.2, 0.1}, {1.7, -0.3}, {0.4, 1.5}});
  EXPECT_EQ(zero_eigenvalues(element_stiffness(tri, tri.reference, 0), 6), 3);
}

TEST(Hourglass, VectorIsOrthogonalToLinearFieldsAndPicksTheHourglassMode) {
  const FemModel model = single_element(ElementType::quad4_1gp, 1.0, distorted_quad);
  const Vec4& gamma = model.reference.hourglass_vector[0];
  double sum = 0.0, gx = 0.0, gy = 0.0, gh = 0.0;
  const std::array<double, 4> h{1.0, -1.0, 1.0, -1.0};
  for (int k = 0; k < 4; ++k) {
    sum += gamma[k];
    gx += gamma[k] * distorted_quad[static_cast<std::size_t>(k)].x();
    gy += gamma[k] * distorted_quad[static_cast<std::size_t>(k)].y();
    gh += gamma[k] * h[static_cast<std::size_t>(k)];
  }
  EXPECT_NEAR(sum, 0.0, 1e-15);
  EXPECT_NEAR(gx, 0.0, 1e-14);
  EXPECT_NEAR(gy, 0.0, 1e-14);
  EXPECT_NEAR(gh, 1.0, 1e-14);
}

TEST(Hourglass, OnAParallelogramTheStabilisedQuadEqualsTheTwoByTwoQuad) {
  // The physical hourglass stiffness is the 2×2 rule's energy of the ξη mode, exactly.
  const std::vector<Vec2> parallelogram{{0.0, 0.0}, {2.0, 0.5}, {2.7, 1.9}, {0.7, 1.4}};
  const FemModel one = single_element(ElementType::quad4_1gp, 1.0, parallelogram);
  const FemModel full = single_element(ElementType::quad4_2x2, 1.0, parallelogram);
  const ElementMatrix k_one = element_stiffness(one, one.reference, 0);
  const ElementMatrix k_full = element_stiffness(full, full.reference, 0);
  EXPECT_LT(max_abs(k_one - k_full), 1e-12 * max_abs(k_full));
  // And differs on a general quadrilateral (the 2×2 element is stiffer in bending there).
  const FemModel one_d = single_element(ElementType::quad4_1gp, 1.0, distorted_quad);
  const FemModel full_d = single_element(ElementType::quad4_2x2, 1.0, distorted_quad);
  const ElementMatrix difference =
      element_stiffness(one_d, one_d.reference, 0) - element_stiffness(full_d, full_d.reference, 0);
  EXPECT_GT(max_abs(difference), 1e-6 * max_abs(k_full));
}

TEST(Hourglass, ExplicitForcesEqualTheStiffnessTimesTheDisplacement) {
  // The incremental hourglass force of the explicit kernels reproduces K u for any u.
  for (const auto type : all_types) {
    SCOPED_TRACE(to_string(type));
    const FemModel model = single_element(
        type, 1.0,
        type == ElementType::tri3 ? std::vector<Vec2>{{0.2, 0.1}, {1.7, -0.3}, {0.4, 1.5}}
                                  : distorted_quad);
    const std::vector<ConstitutiveModel> elastic{ConstitutiveModel::elastic(model.materials[0])};
    FemState state = make_rest_state(model);
    Eigen::Matrix<double, 8, 1> u = Eigen::Matrix<double, 8, 1>::Zero();
    for (int k = 0; k < model.nodes_per_element; ++k) {
      state.velocity[static_cast<std::size_t>(k)] =
          1e-3 * Vec2(std::sin(3.0 * k + 1.0), std::cos(5.0 * k));
      u.segment<2>(2 * k) = state.velocity[static_cast<std::size_t>(k)];
    }
    update_stresses(model, model.reference, elastic, 1.0, false, state);
    const std::vector<Vec2> force = assembled_forces(model, state);
    const Eigen::Matrix<double, 8, 1> ku = element_stiffness(model, model.reference, 0) * u;
    for (int k = 0; k < model.nodes_per_element; ++k) {
      EXPECT_LT((force[static_cast<std::size_t>(k)] + ku.segment<2>(2 * k)).norm(),
                1e-12 * max_abs(ku));
    }
  }
}

TEST(CourantStep, UsesAreaOverLongestEdge) {
  const FemModel quad =
      single_element(ElementType::quad4_1gp, 1.0, {{0.0, 0.0}, {2.0, 0.0}, {2.0, 1.0}, {0.0, 1.0}});
  const double cp = soil().p_wave_speed();
  EXPECT_NEAR(courant_time_step(quad, quad.mesh.nodes, 0.5), 0.5 * (2.0 / 2.0) / cp, 1e-15);
  const FemModel tri = single_element(ElementType::tri3, 1.0, {{0.0, 0.0}, {1.0, 0.0}, {0.0, 1.0}});
  EXPECT_NEAR(courant_time_step(tri, tri.mesh.nodes, 0.5), 0.5 * (2.0 * 0.5 / std::sqrt(2.0)) / cp,
              1e-15);
}

TEST(Geometry, DetectsAnInvertedElement) {
  const FemModel model = single_element(ElementType::quad4_2x2, 1.0, distorted_quad);
  std::vector<Vec2> folded = distorted_quad;
  folded[2] = Vec2(0.2, 0.1);  // the third corner pulled across the first two
  ElementGeometry geometry;
  EXPECT_EQ(compute_geometry(model, folded, geometry), 0);
  EXPECT_EQ(compute_geometry(model, distorted_quad, geometry), -1);
}

TEST(Model, LumpedMassIsTheRowSumAndAddsUpToTheTotalMass) {
  for (const auto type : all_types) {
    const FemModel model = distorted_model(type);
    double total = 0.0;
    for (double m : model.lumped.mass) total += m;
    EXPECT_NEAR(total, soil().density * 12.0, 1e-9 * total);
  }
}

TEST(RayleighStiffnessDamping, IsBetaKTimesTheElementStiffness) {
  // The viscous stress β_K D ε̇ and, for one-point quads, the viscous hourglass force
  // β_K K_q q̇ add −β_K K₀ v to the element forces, K₀ the whole elastic stiffness of
  // element_stiffness (hourglass part included, at any hourglass coefficient): every mode
  // of the element is damped in proportion to its stiffness. On distorted meshes with
  // non-zero stresses and hourglass forces (which the damping must leave as they are), the
  // damped minus the undamped forces equal −β_K K v to round-off.
  const double beta = 0.003;  // s
  std::vector<FemModel> models;
  for (const auto type : all_types) models.push_back(distorted_model(type));
  models.push_back(single_element(ElementType::quad4_1gp, 0.3, distorted_quad));
  for (const FemModel& model : models) {
    SCOPED_TRACE(fmt::format("{}, hourglass coefficient {}", to_string(model.mesh.element_type),
                             model.hourglass_coefficient));
    FemState state = make_rest_state(model);
    for (std::size_t n = 0; n < state.velocity.size(); ++n) {
      const auto k = static_cast<double>(n);
      state.velocity[n] = Vec2(std::sin(3.0 * k + 1.0), std::cos(5.0 * k));
    }
    for (std::size_t gp = 0; gp < state.stress.size(); ++gp) {
      state.stress[gp] = 1e4 * Vec4(1.0, -2.0, 0.5, std::sin(static_cast<double>(gp)));
    }
    for (Vec2& q : state.hourglass_force) q = Vec2(300.0, -700.0);
    const std::vector<Vec2> undamped = assembled_forces(model, state);
    const std::vector<Vec2> damped = assembled_forces(model, state, beta);
    // −β_K K v, assembled element by element.
    std::vector<Vec2> expected(state.velocity.size(), Vec2::Zero());
    const int n = model.nodes_per_element;
    for (Index e = 0; e < model.element_count(); ++e) {
      const Index* nodes = model.mesh.connectivity.data() + e * n;
      Eigen::Matrix<double, 2 * max_nodes_per_element, 1> v =
          Eigen::Matrix<double, 2 * max_nodes_per_element, 1>::Zero();
      for (int k = 0; k < n; ++k) {
        v.segment<2>(2 * k) = state.velocity[static_cast<std::size_t>(nodes[k])];
      }
      const Eigen::Matrix<double, 2 * max_nodes_per_element, 1> kv =
          element_stiffness(model, model.reference, e) * v;
      for (int k = 0; k < n; ++k) {
        expected[static_cast<std::size_t>(nodes[k])] -= beta * kv.segment<2>(2 * k);
      }
    }
    double scale = 0.0;
    for (const Vec2& f : expected) scale = std::max(scale, f.norm());
    ASSERT_GT(scale, 0.0);
    for (std::size_t node = 0; node < expected.size(); ++node) {
      EXPECT_LT((damped[node] - undamped[node] - expected[node]).norm(), 1e-12 * scale)
          << "node " << node;
    }
  }
}

TEST(DampedTimeStep, IsTheClosedFormWithTheCourantAndTheHeavyDampingLimits) {
  // dt = C dt_c (sqrt(1 + ξ²) − ξ), ξ = β_K/dt_c (ξ_max = β_K ω_max/2, ω_max = 2/dt_c).
  const double critical = 2.0e-3, courant = 0.5;
  // β_K = 0: exactly the Courant step, bit for bit (the undamped runs do not change).
  EXPECT_EQ(damped_time_step(critical, courant, 0.0), courant * critical);
  for (const double xi : {1e-3, 0.1, 1.0, 2.5, 10.0}) {
    SCOPED_TRACE(fmt::format("ξ_max = {}", xi));
    const double beta = xi * critical;
    const double dt = damped_time_step(critical, courant, beta);
    EXPECT_NEAR(dt / (courant * critical * (std::sqrt(1.0 + xi * xi) - xi)), 1.0, 1e-12);
    // At C = 1 it is the stability limit of the highest mode: ω² dt² + 2 β_K ω² dt = 4.
    const double limit = damped_time_step(critical, 1.0, beta);
    const double omega = 2.0 / critical;
    EXPECT_NEAR(omega * omega * limit * (limit + 2.0 * beta), 4.0, 4e-12);
  }
  // Light damping: dt = C dt_c (1 − ξ + ξ²/2 + …).
  EXPECT_NEAR(damped_time_step(critical, courant, 1e-6 * critical) / (courant * critical),
              1.0 - 1e-6, 1e-12);
  // Heavy damping: dt → C dt_c/(2ξ) (1 − 1/(4ξ²)), where the naive difference
  // sqrt(1 + ξ²) − ξ would have lost every digit.
  for (const double xi : {1e3, 1e6, 1e9}) {
    const double dt = damped_time_step(critical, courant, xi * critical);
    EXPECT_NEAR(dt / (courant * critical / (2.0 * xi)), 1.0 - 1.0 / (4.0 * xi * xi), 1e-12);
  }
}

}  // namespace
}  // namespace slide::fem

#pragma GCC diagnostic pop
