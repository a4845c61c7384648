// The element kernels: patch tests on distorted meshes, the rigid-body modes of the
// element stiffness, and the hourglass control of the one-point quad.
#include <gtest/gtest.h>

// Eigen's eigensolver, compiled for AVX-512 by GCC 12, trips a false
// -Wmaybe-uninitialized inside _mm512_extractf64x4_pd (GCC bug 105593, fixed in 13).
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <cmath>

#include <Eigen/Eigenvalues>

#include "fem/element_kernels.hpp"
#include "fem/fem_model.hpp"
#include "fem_test_support.hpp"

namespace slide::fem {
namespace {

using testing::distort_interior;
using testing::max_abs;
using testing::rectangle_mesh;
using testing::soil;

const std::array<ElementType, 3> all_types{ElementType::quad4_1gp, ElementType::quad4_2x2,
                                           ElementType::tri3};

FemModel distorted_model(ElementType type) {
  Mesh mesh = rectangle_mesh(type, 4, 3, 4.0, 3.0);
  distort_interior(mesh, 1.0, 0.25);
  return make_model(std::move(mesh), {soil()}, Kinematics::small_strain, 1.0);
}

/// Sum of the element forces at every node (without gravity).
std::vector<Vec2> assembled_forces(const FemModel& model, const FemState& state) {
  std::vector<Vec2> element_force(model.mesh.connectivity.size());
  compute_element_forces(model, model.reference, state, element_force);
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
    for (double m : model.nodal_mass) total += m;
    EXPECT_NEAR(total, soil().density * 12.0, 1e-9 * total);
  }
}

}  // namespace
}  // namespace slide::fem

#pragma GCC diagnostic pop
