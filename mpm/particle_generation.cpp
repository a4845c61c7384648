#include "mpm/particle_generation.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "common/base/error.hpp"
#include "common/geometry/element.hpp"

namespace slide::mpm {

namespace {

/// Appends one particle at x with the layout's volume share.
void add_particle(Particles& particles, const Vec2& x, double volume, const Vec2& size,
                  const Material& material, std::int32_t material_id) {
  const std::size_t p = particles.count();
  particles.resize(p + 1);
  particles.coordinates[p] = x;
  particles.volume[p] = volume;
  particles.mass[p] = material.density * volume;
  particles.size[p] = size;
  particles.material_id[p] = material_id;
  particles.element[p] = -1;
  particles.id[p] = static_cast<std::int64_t>(p);
}

/// Reference coordinates of x in a straight-sided element, by Newton on the isoparametric
/// map (exact in one step for parallelograms and triangles); nullopt when not inside.
bool inside_element(ElementShape shape, const ElementNodes& nodes, const Vec2& x) {
  Vec2 xi = reference_centre(shape);
  for (int iteration = 0; iteration < 20; ++iteration) {
    const Vec2 residual = x - map_to_physical(shape, nodes, xi);
    const Mat2 j = jacobian(shape, nodes, xi);
    const double det = j.determinant();
    if (!(std::abs(det) > 0.0)) return false;
    const Vec2 delta = j.inverse() * residual;
    xi += delta;
    if (delta.norm() < 1e-13) break;
  }
  constexpr double tolerance = 1e-12;
  if (shape == ElementShape::quad4) {
    return std::abs(xi.x()) <= 1.0 + tolerance && std::abs(xi.y()) <= 1.0 + tolerance;
  }
  return xi.x() >= -tolerance && xi.y() >= -tolerance && xi.x() + xi.y() <= 1.0 + tolerance;
}

}  // namespace

Particles generate_box_particles(const GridGeometry& grid, const Vec2& lower, const Vec2& upper,
                                 int per_cell_x, int per_cell_y, const MaterialTable& materials,
                                 std::int32_t material_id) {
  if (material_id < 0 || static_cast<std::size_t>(material_id) >= materials.size()) {
    throw Error("generate_box_particles: unknown material id {}", material_id);
  }
  const Material& material = materials[static_cast<std::size_t>(material_id)];
  const double h = grid.cell_size;
  const auto rule = tensor_gauss_legendre(per_cell_x, per_cell_y);
  const Vec2 size(h / per_cell_x, h / per_cell_y);
  const int cx0 = static_cast<int>(std::lround((lower.x() - grid.origin.x()) / h));
  const int cx1 = static_cast<int>(std::lround((upper.x() - grid.origin.x()) / h));
  const int cy0 = static_cast<int>(std::lround((lower.y() - grid.origin.y()) / h));
  const int cy1 = static_cast<int>(std::lround((upper.y() - grid.origin.y()) / h));
  Particles particles;
  for (int cx = cx0; cx < cx1; ++cx) {
    for (int cy = cy0; cy < cy1; ++cy) {
      const Vec2 corner = grid.origin + h * Vec2(cx, cy);
      for (const QuadraturePoint& q : rule) {
        const Vec2 x = corner + 0.5 * h * (q.xi + Vec2(1.0, 1.0));
        add_particle(particles, x, h * h * q.weight / 4.0, size, material, material_id);
      }
    }
  }
  return particles;
}

Particles generate_mesh_particles(const GridGeometry& grid, const Mesh& mesh, int per_cell_x,
                                  int per_cell_y, const MaterialTable& materials, const Part& part,
                                  std::size_t* whole_count) {
  const double h = grid.cell_size;
  const auto rule = tensor_gauss_legendre(per_cell_x, per_cell_y);
  const Vec2 size(h / per_cell_x, h / per_cell_y);
  const ElementShape shape = mesh.shape();
  // Visit each element's bounding box of cells: every candidate point is tested against
  // the elements whose box holds it, and a point on a shared edge goes to the first.
  std::vector<std::int64_t> owner(grid.cell_count() * rule.size(), -1);
  for (Index e = 0; e < mesh.element_count(); ++e) {
    const ElementNodes nodes = mesh.element_nodes(e, mesh.nodes);
    const int n = mesh.nodes_per_element();
    Vec2 lo = nodes.row(0).transpose(), hi = lo;
    for (int k = 1; k < n; ++k) {
      lo = lo.cwiseMin(nodes.row(k).transpose());
      hi = hi.cwiseMax(nodes.row(k).transpose());
    }
    const int cx0 = std::max(0, static_cast<int>(std::floor((lo.x() - grid.origin.x()) / h)));
    const int cy0 = std::max(0, static_cast<int>(std::floor((lo.y() - grid.origin.y()) / h)));
    const int cx1 =
        std::min(grid.cells_x - 1, static_cast<int>(std::floor((hi.x() - grid.origin.x()) / h)));
    const int cy1 =
        std::min(grid.cells_y - 1, static_cast<int>(std::floor((hi.y() - grid.origin.y()) / h)));
    for (int cx = cx0; cx <= cx1; ++cx) {
      for (int cy = cy0; cy <= cy1; ++cy) {
        const std::size_t cell =
            static_cast<std::size_t>(cx) * static_cast<std::size_t>(grid.cells_y) +
            static_cast<std::size_t>(cy);
        const Vec2 corner = grid.origin + h * Vec2(cx, cy);
        for (std::size_t q = 0; q < rule.size(); ++q) {
          std::int64_t& slot = owner[cell * rule.size() + q];
          if (slot >= 0) continue;
          const Vec2 x = corner + 0.5 * h * (rule[q].xi + Vec2(1.0, 1.0));
          if (x.x() < lo.x() || x.x() > hi.x() || x.y() < lo.y() || x.y() > hi.y()) continue;
          if (inside_element(shape, nodes, x)) slot = e;
        }
      }
    }
  }
  // The body's rows are its points in cell order; this part makes rows [first, end).
  const auto total = static_cast<std::size_t>(
      std::count_if(owner.begin(), owner.end(), [](std::int64_t e) { return e >= 0; }));
  if (total == 0) {
    throw Error("pure MPM: the body's mesh does not overlap the grid (no particle generated)");
  }
  const auto [first, end] = part.rows(total);
  Particles particles;
  std::size_t row = 0;
  for (std::size_t cell = 0; cell < grid.cell_count() && row < end; ++cell) {
    const int cx = static_cast<int>(cell / static_cast<std::size_t>(grid.cells_y));
    const int cy = static_cast<int>(cell % static_cast<std::size_t>(grid.cells_y));
    const Vec2 corner = grid.origin + h * Vec2(cx, cy);
    for (std::size_t q = 0; q < rule.size(); ++q) {
      const std::int64_t e = owner[cell * rule.size() + q];
      if (e < 0) continue;
      if (row++ < first || row > end) continue;
      const std::int32_t material_id = mesh.material_id[static_cast<std::size_t>(e)];
      const Vec2 x = corner + 0.5 * h * (rule[q].xi + Vec2(1.0, 1.0));
      add_particle(particles, x, h * h * rule[q].weight / 4.0, size,
                   materials.at(static_cast<std::size_t>(material_id)), material_id);
      particles.id.back() = static_cast<std::int64_t>(row - 1);  // its row in the whole body
    }
  }
  if (whole_count != nullptr) *whole_count = total;
  return particles;
}

std::vector<double> mesh_surface_heights(const Mesh& mesh, std::span<const Vec2> points) {
  // The distinct x positions of the points, and for each the highest boundary crossing.
  std::vector<double> xs(points.size());
  for (std::size_t p = 0; p < points.size(); ++p) xs[p] = points[p].x();
  std::sort(xs.begin(), xs.end());
  xs.erase(std::unique(xs.begin(), xs.end()), xs.end());
  std::vector<double> top(xs.size(), -std::numeric_limits<double>::infinity());
  const int n = mesh.nodes_per_element();
  for (Index e = 0; e < mesh.element_count(); ++e) {
    const auto element = mesh.element(e);
    for (int k = 0; k < n; ++k) {
      const Vec2& a = mesh.nodes[static_cast<std::size_t>(element[static_cast<std::size_t>(k)])];
      const Vec2& b =
          mesh.nodes[static_cast<std::size_t>(element[static_cast<std::size_t>((k + 1) % n)])];
      const double x0 = std::min(a.x(), b.x()), x1 = std::max(a.x(), b.x());
      auto first = std::lower_bound(xs.begin(), xs.end(), x0);
      for (auto it = first; it != xs.end() && *it <= x1; ++it) {
        const double y = x1 > x0 ? a.y() + (b.y() - a.y()) * (*it - a.x()) / (b.x() - a.x())
                                 : std::max(a.y(), b.y());
        double& t = top[static_cast<std::size_t>(it - xs.begin())];
        t = std::max(t, y);
      }
    }
  }
  std::vector<double> heights(points.size());
  for (std::size_t p = 0; p < points.size(); ++p) {
    const auto it = std::lower_bound(xs.begin(), xs.end(), points[p].x());
    heights[p] = top[static_cast<std::size_t>(it - xs.begin())];
  }
  return heights;
}

void apply_k0_stresses(Particles& particles, const MaterialTable& materials,
                       std::span<const double> surface_height, double gravity) {
  for (std::size_t p = 0; p < particles.count(); ++p) {
    const Material& m = materials.at(static_cast<std::size_t>(particles.material_id[p]));
    const double depth = std::max(surface_height[p] - particles.coordinates[p].y(), 0.0);
    const double syy = -m.density * gravity * depth;
    particles.stress[p] = Vec4(m.k0() * syy, syy, m.k0() * syy, 0.0);
  }
}

}  // namespace slide::mpm
