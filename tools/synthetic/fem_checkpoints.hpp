// FE checkpoints built in memory for the transfer tests and benchmarks (tools/synthetic:
// inputs made in code, which both may use): a rectangular
// block of nx × ny cells (quads, or each cell split into two triangles), optionally
// deformed by a displacement field, with analytic nodal velocities and Gauss-point
// stresses and strains. Everything a checkpoint holds is filled consistently (current
// coordinates = reference + displacement, volumes from the node positions, Gauss points
// at the element rule's points mapped onto the current nodes), so the same object can be
// written with write_checkpoint for the command-line tests.
#pragma once

#include <cmath>
#include <functional>

#include "common/geometry/element.hpp"
#include "common/io/checkpoint.hpp"
#include "common/physics/constitutive.hpp"
#include "tools/synthetic/soil.hpp"

namespace slide::synthetic {

struct BlockFields {
  /// u(X) of the reference position; zero by default.
  std::function<Vec2(const Vec2&)> displacement = [](const Vec2&) { return Vec2::Zero(); };
  /// v(x) of the current position; zero by default.
  std::function<Vec2(const Vec2&)> velocity = [](const Vec2&) { return Vec2::Zero(); };
  /// σ(x) and ε(x) of the current Gauss point position; zero by default.
  std::function<Vec4(const Vec2&)> stress = [](const Vec2&) { return Vec4::Zero(); };
  std::function<Vec4(const Vec2&)> strain = [](const Vec2&) { return Vec4::Zero(); };
  std::function<MaterialState(const Vec2&)> state = [](const Vec2&) { return MaterialState{}; };
};

/// A width × height block with its lower-left corner at the origin.
inline FemCheckpoint make_block(int nx, int ny, double width, double height, ElementType type,
                                const BlockFields& fields = {}, double density = 1700.0) {
  FemCheckpoint fem;
  fem.header.kind = CheckpointKind::fem;
  fem.header.producer = "transfer tests";
  fem.header.time = 2.0;
  fem.header.step = 1234;
  fem.header.case_name = "transfer-test";
  fem.header.pe0 = 1.0e6;
  Mesh& mesh = fem.mesh;
  mesh.element_type = type;
  const double hx = width / nx, hy = height / ny;
  auto node = [nx](int i, int j) { return static_cast<Index>(j * (nx + 1) + i); };
  for (int j = 0; j <= ny; ++j) {
    for (int i = 0; i <= nx; ++i) mesh.nodes.emplace_back(i * hx, j * hy);
  }
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      const Index a = node(i, j), b = node(i + 1, j), c = node(i + 1, j + 1), d = node(i, j + 1);
      if (shape_of(type) == ElementShape::quad4) {
        mesh.connectivity.insert(mesh.connectivity.end(), {a, b, c, d});
        mesh.material_id.push_back(0);
      } else {
        // Alternate the diagonal so the mesh has no preferred direction.
        if ((i + j) % 2 == 0) {
          mesh.connectivity.insert(mesh.connectivity.end(), {a, b, c, a, c, d});
        } else {
          mesh.connectivity.insert(mesh.connectivity.end(), {a, b, d, b, c, d});
        }
        mesh.material_id.insert(mesh.material_id.end(), {0, 0});
      }
    }
  }
  NodeSet base{"base", {}, Vec2(0.0, -1.0)};
  for (int i = 0; i <= nx; ++i) base.nodes.push_back(node(i, 0));
  mesh.node_sets.push_back(base);
  fem.boundary_conditions.push_back(BoundaryCondition::friction);
  fem.friction_coefficient = 0.466;

  for (const Vec2& X : mesh.nodes) {
    const Vec2 u = fields.displacement(X);
    fem.coordinates.push_back(X + u);
    fem.displacement.push_back(u);
    fem.velocity.push_back(fields.velocity(X + u));
    fem.acceleration.push_back(Vec2::Zero());
    fem.pore_pressure.push_back(0.0);
  }
  const ElementShape shape = mesh.shape();
  const auto rule = quadrature_rule(type);
  for (Index e = 0; e < mesh.element_count(); ++e) {
    const ElementNodes x0 = mesh.element_nodes(e, mesh.nodes);
    const ElementNodes x = mesh.element_nodes(e, fem.coordinates);
    fem.volume_reference.push_back(element_area(shape, x0));
    fem.volume.push_back(element_area(shape, x));
    const Vec2 centre = reference_centre(shape);
    fem.jacobian_ratio.push_back(jacobian(shape, x, centre).determinant() /
                                 jacobian(shape, x0, centre).determinant());
    for (const auto& q : rule) {
      const Vec2 xg = map_to_physical(shape, x, q.xi);
      fem.gauss_element.push_back(e);
      fem.gauss_local_coordinates.push_back(q.xi);
      fem.gauss_coordinates.push_back(xg);
      fem.gauss_weight.push_back(q.weight);
      fem.stress.push_back(fields.stress(xg));
      fem.strain.push_back(fields.strain(xg));
      fem.eps_q.push_back(deviatoric_strain(fem.strain.back()));
      fem.material_state.push_back(fields.state(xg));
    }
  }
  fem.materials.push_back(soil(MaterialModel::mohr_coulomb, density));
  return fem;
}

/// A smooth, strongly non-affine displacement: every element becomes a general
/// quadrilateral (or a sheared triangle) of the same orientation.
inline std::function<Vec2(const Vec2&)> distortion(double amplitude) {
  return [amplitude](const Vec2& X) {
    return Vec2(
        amplitude * std::sin(1.3 * X.y() + 0.4) * std::cos(0.7 * X.x()) + 0.05 * X.y(),
        amplitude * std::cos(1.1 * X.x() - 0.2) * std::sin(0.9 * X.y() + 0.3) - 0.03 * X.x());
  };
}

/// The exact geostatic state of a level column of height H (docs/method.md §3):
/// σyy = −ρ g (H − y), σxx = σzz = K0 σyy, K0 = ν/(1 − ν).
inline std::function<Vec4(const Vec2&)> geostatic_stress(double density, double poisson_ratio,
                                                         double height) {
  const double k0 = poisson_ratio / (1.0 - poisson_ratio);
  return [=](const Vec2& x) {
    const double syy = -density * gravity_acceleration * (height - x.y());
    return Vec4(k0 * syy, syy, k0 * syy, 0.0);
  };
}

}  // namespace slide::synthetic
