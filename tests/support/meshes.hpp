// Small meshes the tests build by hand: structured rectangles of every element type,
// and their interior nodes moved to make a distorted but valid mesh.
#pragma once

#include <algorithm>
#include <cmath>

#include "common/geometry/mesh.hpp"

namespace slide::testing {

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

}  // namespace slide::testing
