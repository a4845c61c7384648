// Small meshes, materials and case files the fem tests build by hand.
#pragma once

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "common/material.hpp"
#include "common/mesh.hpp"
#include "fem/fem_model.hpp"

namespace slide::fem::testing {

/// The soil of the cases (METHOD.md §7), linear elastic or Mohr–Coulomb.
inline Material soil(MaterialModel model = MaterialModel::linear_elastic) {
  Material m;
  m.name = "soil";
  m.model = model;
  m.density = 1700.0;
  m.youngs_modulus = 23.8e6;
  m.poisson_ratio = 0.23;
  m.friction_angle = 22.2;
  m.cohesion = 1000.0;
  m.tension_cutoff = m.apex_stress();
  return m;
}

/// A structured nx × ny mesh of the rectangle [x0, x0 + lx] × [0, ly] with node sets
/// left, right, base and top; tri3 splits every cell along the diagonal (i, j)–(i+1, j+1).
inline Mesh rectangle_mesh(ElementType type, int nx, int ny, double lx, double ly,
                           double x0 = 0.0) {
  Mesh mesh;
  mesh.element_type = type;
  const auto node = [&](int i, int j) { return static_cast<Index>(j * (nx + 1) + i); };
  for (int j = 0; j <= ny; ++j) {
    for (int i = 0; i <= nx; ++i) mesh.nodes.emplace_back(x0 + lx * i / nx, ly * j / ny);
  }
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      const Index a = node(i, j), b = node(i + 1, j), c = node(i + 1, j + 1), d = node(i, j + 1);
      if (type == ElementType::tri3) {
        mesh.connectivity.insert(mesh.connectivity.end(), {a, b, c, a, c, d});
        mesh.material_id.insert(mesh.material_id.end(), {0, 0});
      } else {
        mesh.connectivity.insert(mesh.connectivity.end(), {a, b, c, d});
        mesh.material_id.push_back(0);
      }
    }
  }
  NodeSet left{"left", {}, Vec2(-1.0, 0.0)}, right{"right", {}, Vec2(1.0, 0.0)};
  NodeSet base{"base", {}, Vec2(0.0, -1.0)}, top{"top", {}, Vec2(0.0, 1.0)};
  for (int j = 0; j <= ny; ++j) {
    left.nodes.push_back(node(0, j));
    right.nodes.push_back(node(nx, j));
  }
  for (int i = 0; i <= nx; ++i) {
    base.nodes.push_back(node(i, 0));
    top.nodes.push_back(node(i, ny));
  }
  mesh.node_sets = {left, right, base, top};
  return mesh;
}

/// Moves every interior node of `mesh` by a deterministic pseudo-random offset of up to
/// `fraction` of the cell size h: a distorted but valid mesh.
inline void distort_interior(Mesh& mesh, double h, double fraction) {
  double lo_x = 1e300, hi_x = -1e300, lo_y = 1e300, hi_y = -1e300;
  for (const Vec2& x : mesh.nodes) {
    lo_x = std::min(lo_x, x.x());
    hi_x = std::max(hi_x, x.x());
    lo_y = std::min(lo_y, x.y());
    hi_y = std::max(hi_y, x.y());
  }
  const double eps = 1e-9 * h;
  for (std::size_t n = 0; n < mesh.nodes.size(); ++n) {
    Vec2& x = mesh.nodes[n];
    if (x.x() < lo_x + eps || x.x() > hi_x - eps || x.y() < lo_y + eps || x.y() > hi_y - eps) {
      continue;
    }
    const double k = static_cast<double>(n);
    x += fraction * h * Vec2(std::sin(1.7 * k + 0.3), std::cos(2.3 * k + 0.1));
  }
}

/// Largest |entry| by a plain loop (Eigen's vectorised reductions trip a false
/// -Wmaybe-uninitialized of GCC 12 with AVX-512).
template <typename Matrix>
double max_abs(const Matrix& m) {
  double largest = 0.0;
  for (Eigen::Index i = 0; i < m.rows(); ++i) {
    for (Eigen::Index j = 0; j < m.cols(); ++j) largest = std::max(largest, std::abs(m(i, j)));
  }
  return largest;
}

inline void write_file(const std::filesystem::path& path, const std::string& text) {
  std::filesystem::create_directories(path.parent_path());
  std::ofstream(path) << text;
}

/// A column case for fem-solve: `width` × `height` m of the soil on a rough base, the
/// right face released in the failure stage (METHOD.md §7 column cases, scaled down).
struct ColumnCase {
  std::string name = "test-column";
  double width = 10.0;
  double height = 8.0;
  double element_size = 1.0;
  std::string element = "quad4-1gp";
  std::string model = "mohr-coulomb";
  std::string kinematics = "small-strain";
  double end_time = 0.4;
  double checkpoint_every = 0.2;
  double output_every = 0.1;
  double cohesion = 1000.0;
  double friction_angle = 22.2;
  double time_step = 0.0;
  /// Replaces the generated [mesh] table when not empty.
  std::string mesh;
  /// More lines of the [fem] table.
  std::string extra_fem;
  std::string geostatic_boundaries = "left = \"roller\"\nright = \"roller\"\nbase = \"roller\"\n";
  std::string failure_boundaries = "left = \"roller\"\nright = \"free\"\nbase = \"friction\"\n";

  std::string text() const {
    const std::string mesh_table = !mesh.empty()
                                       ? mesh
                                       : "[mesh]\ngenerator = \"profile\"\nelement = \"" + element +
                                             "\"\nelement_size = " + std::to_string(element_size) +
                                             "\nsurface = [[0.0, " + std::to_string(height) +
                                             "], [" + std::to_string(width) + ", " +
                                             std::to_string(height) + "]]\nmaterial = \"soil\"\n";
    return "[case]\nname = \"" + name + "\"\n\n[[materials]]\nname = \"soil\"\nmodel = \"" + model +
           "\"\ndensity = 1700.0\nyoungs_modulus = 23.8e6\npoisson_ratio = 0.23\n"
           "friction_angle = " +
           std::to_string(friction_angle) + "\ncohesion = " + std::to_string(cohesion) + "\n\n" +
           mesh_table + "\n[fem]\nkinematics = \"" + kinematics +
           "\"\nend_time = " + std::to_string(end_time) +
           "\ncheckpoint_every = " + std::to_string(checkpoint_every) +
           "\noutput_every = " + std::to_string(output_every) +
           "\ntime_step = " + std::to_string(time_step) + "\nfriction_coefficient = 0.466\n" +
           extra_fem + "\n[fem.geostatic.boundaries]\n" + geostatic_boundaries +
           "\n[fem.failure.boundaries]\n" + failure_boundaries +
           "\n[mpm]\ndomain = [[0.0, 0.0], [40.0, 20.0]]\ncell_size = 1.0\nend_time = 1.0\n"
           "friction_coefficient = 0.466\n\n[mpm.boundaries]\nleft = \"roller\"\n"
           "right = \"roller\"\nbase = \"friction\"\ntop = \"free\"\n\n[metrics]\n"
           "initial_length = " +
           std::to_string(width) + "\ninitial_height = " + std::to_string(height) + "\n";
  }
};

}  // namespace slide::fem::testing
