#include "mpm/grid.hpp"

#include <algorithm>
#include <cmath>

#include "common/base/error.hpp"
#include "mpm/shape_functions.hpp"

namespace slide::mpm {

GridGeometry GridGeometry::covering(const Vec2& domain_min, const Vec2& domain_max,
                                    double cell_size) {
  if (!(cell_size > 0.0) || !std::isfinite(cell_size)) {
    throw Error("mpm.cell_size = {} is not admissible (expected h > 0 m)", cell_size);
  }
  const Vec2 extent = domain_max - domain_min;
  if (!(extent.x() > 0.0) || !(extent.y() > 0.0) || !extent.allFinite()) {
    throw Error("mpm.domain [[{}, {}], [{}, {}]] is empty (expected max > min in x and y)",
                domain_min.x(), domain_min.y(), domain_max.x(), domain_max.y());
  }
  // A whole number of cells; a relative slack of 1e-9 keeps 200/1 from becoming 201.
  // Counted in floating point first: the int conversion of 1e300 cells is undefined.
  const double columns = std::ceil(extent.x() / cell_size - 1e-9);
  const double rows = std::ceil(extent.y() / cell_size - 1e-9);
  constexpr double max_nodes = 2.0e8;
  if (!((columns + 3.0) * (rows + 3.0) <= max_nodes)) {
    throw Error(
        "mpm.domain [[{}, {}], [{}, {}]] with mpm.cell_size = {} m makes {:.3g} × {:.3g} cells, "
        "more than the {:g} grid nodes mpm-solve holds",
        domain_min.x(), domain_min.y(), domain_max.x(), domain_max.y(), cell_size, columns, rows,
        max_nodes);
  }
  GridGeometry g;
  g.origin = domain_min;
  g.cell_size = cell_size;
  g.cells_x = static_cast<int>(columns);
  g.cells_y = static_cast<int>(rows);
  return g;
}

Vec2 GridGeometry::node_position(std::size_t index) const {
  const auto rows = static_cast<std::size_t>(node_rows());
  const int i = static_cast<int>(index / rows) - 1;
  const int j = static_cast<int>(index % rows) - 1;
  return origin + cell_size * Vec2(i, j);
}

std::size_t GridGeometry::cell_of(const Vec2& x) const {
  // floor_cells: std::floor's value in a third of its instructions on the baseline ISA.
  const int cx =
      std::clamp(static_cast<int>(floor_cells((x.x() - origin.x()) / cell_size)), 0, cells_x - 1);
  const int cy =
      std::clamp(static_cast<int>(floor_cells((x.y() - origin.y()) / cell_size)), 0, cells_y - 1);
  return static_cast<std::size_t>(cx) * static_cast<std::size_t>(cells_y) +
         static_cast<std::size_t>(cy);
}

GridBoundaries GridBoundaries::from(const BoundaryTable& table, double friction_coefficient) {
  GridBoundaries b;
  b.friction_coefficient = friction_coefficient;
  const std::array<std::pair<const char*, Vec2>, 4> edges = {{{"left", Vec2(-1.0, 0.0)},
                                                              {"right", Vec2(1.0, 0.0)},
                                                              {"base", Vec2(0.0, -1.0)},
                                                              {"top", Vec2(0.0, 1.0)}}};
  for (std::size_t e = 0; e < edges.size(); ++e) {
    b.edge[e].normal = edges[e].second;
    const auto found = table.find(edges[e].first);
    b.edge[e].condition = found == table.end() ? BoundaryCondition::free : found->second;
  }
  for (const auto& [name, condition] : table) {
    if (name != "left" && name != "right" && name != "base" && name != "top") {
      throw Error("mpm.boundaries.{}: unknown grid edge (expected left, right, base or top)", name);
    }
  }
  return b;
}

int GridBoundaries::constraints_of(const GridGeometry& grid, int i, int j,
                                   std::array<NodalConstraint, 2>& out) const {
  int n = 0;
  auto add = [&](GridEdge e) {
    if (edge[e].condition != BoundaryCondition::free) out[static_cast<std::size_t>(n++)] = edge[e];
  };
  if (i <= 0) add(edge_left);
  if (i >= grid.cells_x) add(edge_right);
  if (j <= 0) add(edge_base);
  if (j >= grid.cells_y) add(edge_top);
  return n;
}

void GridState::resize(const GridGeometry& grid) {
  sums.assign(grid.node_count(), NodeSums{});
  motion.assign(grid.node_count(), NodeMotion{});
  remapped_velocity.assign(grid.node_count(), Vec2::Zero());
  cell_averages.assign(grid.node_count(), CellAverages{});
  active_begin = active_end = 0;
}

std::size_t GridState::bytes() const {
  return sums.capacity() * sizeof(NodeSums) + motion.capacity() * sizeof(NodeMotion) +
         remapped_velocity.capacity() * sizeof(Vec2) +
         cell_averages.capacity() * sizeof(CellAverages);
}

}  // namespace slide::mpm
