// The FE mesh of a case: the two structured generators of the [mesh] table ("profile",
// "blocks"), the dispatch to the Gmsh reader, and the checks every mesh passes before a
// solver sees it (mesh_generation.hpp).
//
// Node numbering is deterministic: grid nodes row by row (x or u fastest), blocks in the
// order the case lists them, a node shared by several blocks numbered where it first
// appears.
//
// tri3 meshes split every grid cell (i, j) into two counter-clockwise triangles with the
// corners a = (i, j), b = (i+1, j), c = (i+1, j+1), d = (i, j+1):
//   (i + j) even: diagonal a–c, triangles (a, b, c) and (a, c, d)
//   (i + j) odd : diagonal b–d, triangles (a, b, d) and (b, c, d)
// so the diagonals alternate like a chequerboard (the "union jack" pattern): every
// other interior node joins eight triangles, and no direction is preferred.
#include "common/input/mesh_generation.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "common/base/error.hpp"
#include "common/io/gmsh_reader.hpp"
#include "common/io/opensees_reader.hpp"

namespace slide {
namespace {

// Two points closer than this fraction of the smallest element edge are the same point;
// a node this close to x_min, x_max or y_min belongs to "left", "right" or "base".
constexpr double relative_tolerance = 1e-6;

std::string material_names(const MaterialTable& materials) {
  std::string names;
  for (const auto& m : materials) names += (names.empty() ? "" : ", ") + m.name;
  return names.empty() ? "none" : names;
}

std::int32_t material_id_of(const MaterialTable& materials, std::string_view name,
                            std::string_view where) {
  for (std::size_t i = 0; i < materials.size(); ++i) {
    if (materials[i].name == name) return static_cast<std::int32_t>(i);
  }
  throw Error("{}: unknown material \"{}\" (materials of the case: {})", where, name,
              material_names(materials));
}

double cross(const Vec2& a, const Vec2& b) {
  return a.x() * b.y() - a.y() * b.x();
}

std::string point_text(const Vec2& p) {
  return fmt::format("({}, {})", p.x(), p.y());
}

/// Nodes of a block edge (side k from corner k to corner k+1): evenly spaced, as the
/// transfinite map places them.
std::vector<Vec2> edge_nodes(const MeshBlock& block, int side) {
  const Vec2& a = block.corners[static_cast<std::size_t>(side)];
  const Vec2& b = block.corners[static_cast<std::size_t>((side + 1) % 4)];
  const int cells = side % 2 == 0 ? block.cells_u : block.cells_v;
  std::vector<Vec2> nodes;
  for (int i = 0; i <= cells; ++i) nodes.push_back(a + (b - a) * (static_cast<double>(i) / cells));
  return nodes;
}

/// Appends the elements of an nu × nv grid of cells whose node (i, j) is `node_of(i, j)`:
/// one quad per cell, or two triangles with the alternating diagonal of the file comment.
template <typename NodeOf>
void append_grid_elements(Mesh& mesh, int nu, int nv, NodeOf node_of, std::int32_t material) {
  const bool triangles = mesh.shape() == ElementShape::tri3;
  for (int j = 0; j < nv; ++j) {
    for (int i = 0; i < nu; ++i) {
      const Index a = node_of(i, j);
      const Index b = node_of(i + 1, j);
      const Index c = node_of(i + 1, j + 1);
      const Index d = node_of(i, j + 1);
      if (!triangles) {
        mesh.connectivity.insert(mesh.connectivity.end(), {a, b, c, d});
        mesh.material_id.push_back(material);
      } else if ((i + j) % 2 == 0) {
        mesh.connectivity.insert(mesh.connectivity.end(), {a, b, c, a, c, d});
        mesh.material_id.insert(mesh.material_id.end(), {material, material});
      } else {
        mesh.connectivity.insert(mesh.connectivity.end(), {a, b, d, b, c, d});
        mesh.material_id.insert(mesh.material_id.end(), {material, material});
      }
    }
  }
}

/// The shortest element edge of the mesh (0 when an element has coincident nodes).
double smallest_edge(const Mesh& mesh) {
  double h_min = std::numeric_limits<double>::infinity();
  const int n = mesh.nodes_per_element();
  for (Index e = 0; e < mesh.element_count(); ++e) {
    const auto nodes = mesh.element(e);
    for (int k = 0; k < n; ++k) {
      const Vec2& p = mesh.nodes[static_cast<std::size_t>(nodes[static_cast<std::size_t>(k)])];
      const Vec2& q =
          mesh.nodes[static_cast<std::size_t>(nodes[static_cast<std::size_t>((k + 1) % n)])];
      h_min = std::min(h_min, (q - p).norm());
    }
  }
  return h_min;
}

/// Adds "left", "right" and "base": the nodes within `tolerance` of x_min, x_max, y_min.
void add_boundary_node_sets(Mesh& mesh, double tolerance) {
  double x_min = std::numeric_limits<double>::infinity();
  double x_max = -x_min;
  double y_min = x_min;
  for (const Vec2& p : mesh.nodes) {
    x_min = std::min(x_min, p.x());
    x_max = std::max(x_max, p.x());
    y_min = std::min(y_min, p.y());
  }
  NodeSet left{"left", {}, Vec2(-1.0, 0.0)};
  NodeSet right{"right", {}, Vec2(1.0, 0.0)};
  NodeSet base{"base", {}, Vec2(0.0, -1.0)};
  for (Index i = 0; i < mesh.node_count(); ++i) {
    const Vec2& p = mesh.nodes[static_cast<std::size_t>(i)];
    if (std::abs(p.x() - x_min) <= tolerance) left.nodes.push_back(i);
    if (std::abs(p.x() - x_max) <= tolerance) right.nodes.push_back(i);
    if (std::abs(p.y() - y_min) <= tolerance) base.nodes.push_back(i);
  }
  mesh.node_sets.push_back(std::move(left));
  mesh.node_sets.push_back(std::move(right));
  mesh.node_sets.push_back(std::move(base));
}

/// Finds points within a tolerance of each other: a hash of square cells of the
/// tolerance's size, so a match lies in the point's cell or one of its eight neighbours.
class PointLocator {
 public:
  explicit PointLocator(double tolerance) : tolerance_(tolerance) {}

  /// The first stored point within the tolerance of `p` for which `accept(index)` holds,
  /// or -1.
  template <typename Accept>
  Index find(const Vec2& p, const std::vector<Vec2>& points, Accept accept) const {
    const auto [cx, cy] = cell_of(p);
    for (std::int64_t dy = -1; dy <= 1; ++dy) {
      for (std::int64_t dx = -1; dx <= 1; ++dx) {
        const auto it = cells_.find({cx + dx, cy + dy});
        if (it == cells_.end()) continue;
        for (const Index m : it->second) {
          if ((points[static_cast<std::size_t>(m)] - p).norm() <= tolerance_ && accept(m)) {
            return m;
          }
        }
      }
    }
    return -1;
  }
  void insert(const Vec2& p, Index index) { cells_[cell_of(p)].push_back(index); }

 private:
  std::pair<std::int64_t, std::int64_t> cell_of(const Vec2& p) const {
    return {static_cast<std::int64_t>(std::floor(p.x() / tolerance_)),
            static_cast<std::int64_t>(std::floor(p.y() / tolerance_))};
  }
  double tolerance_;
  std::map<std::pair<std::int64_t, std::int64_t>, std::vector<Index>> cells_;
};

double distance_to_segment(const Vec2& p, const Vec2& a, const Vec2& b) {
  const Vec2 ab = b - a;
  const double length2 = ab.squaredNorm();
  const double t = length2 > 0.0 ? std::clamp((p - a).dot(ab) / length2, 0.0, 1.0) : 0.0;
  return (p - (a + t * ab)).norm();
}

/// Throws when a boundary table names a node set the mesh does not have.
void check_boundary_names(const Mesh& mesh, const BoundaryTable& table, std::string_view table_key,
                          std::string_view source, bool from_gmsh) {
  for (const auto& [name, condition] : table) {
    if (mesh.find_node_set(name) != nullptr) continue;
    std::string known;
    for (const auto& set : mesh.node_sets) known += (known.empty() ? "" : ", ") + set.name;
    if (from_gmsh) {
      throw Error(
          "{}: boundary '{}' used in {} has no physical group of that name (physical "
          "lines: {})",
          source, name, table_key, known.empty() ? "none" : known);
    }
    throw Error("{}: boundary '{}' used in {} is not a node set of the generated mesh ({})", source,
                name, table_key, known);
  }
}

/// Throws when the MPM grid does not hold the whole mesh: the material points of a
/// transfer (or of pure MPM) would start outside it. Checked for every mesh source, so
/// that a Gmsh body too large for the grid is refused before the FE phase runs, not
/// when mpm-solve starts from its particles (the case reader checks the generated
/// geometries already, from their outlines).
void check_body_in_grid(const Mesh& mesh, const MpmSpec& mpm, std::string_view case_source,
                        std::string_view mesh_source) {
  if (mesh.node_count() == 0) return;
  Vec2 lo = mesh.nodes[0];
  Vec2 hi = lo;
  for (const Vec2& x : mesh.nodes) {
    lo = lo.cwiseMin(x);
    hi = hi.cwiseMax(x);
  }
  const bool inside =
      (lo.array() >= mpm.domain_min.array()).all() && (hi.array() <= mpm.domain_max.array()).all();
  if (inside) return;
  throw Error(
      "{}: mpm.domain ({}, {})–({}, {}) m does not contain the body of {}, ({}, {})–({}, {}) m: "
      "its material points would start outside the MPM grid; widen mpm.domain",
      case_source, mpm.domain_min.x(), mpm.domain_min.y(), mpm.domain_max.x(), mpm.domain_max.y(),
      mesh_source, lo.x(), lo.y(), hi.x(), hi.y());
}

/// The blocks of a "blocks" mesh, checked and mapped to their grids of nodes, before
/// coincident nodes are merged.
struct MappedBlocks {
  std::vector<std::vector<Vec2>> grids;                    ///< each block's nodes, u fastest
  std::vector<std::int32_t> material;                      ///< each block's material id
  double h_min = std::numeric_limits<double>::infinity();  ///< shortest grid edge
  double extent = 0.0;                                     ///< largest |coordinate| of a corner
};

/// The grid of nodes of `block` by the bilinear map of its corners (transfinite
/// interpolation with straight sides): x(s, t) = Σ corners × (1−s|s)(1−t|t).
std::vector<Vec2> block_grid(const MeshBlock& block) {
  const auto& p = block.corners;
  const int nu = block.cells_u;
  const int nv = block.cells_v;
  std::vector<Vec2> grid;
  grid.reserve(static_cast<std::size_t>((nu + 1) * (nv + 1)));
  for (int j = 0; j <= nv; ++j) {
    const double t = static_cast<double>(j) / nv;
    for (int i = 0; i <= nu; ++i) {
      const double s = static_cast<double>(i) / nu;
      grid.push_back((1.0 - s) * (1.0 - t) * p[0] + s * (1.0 - t) * p[1] + s * t * p[2] +
                     (1.0 - s) * t * p[3]);
    }
  }
  return grid;
}

/// The shortest edge between neighbouring nodes of an nu × nv grid of cells.
double smallest_grid_edge(const std::vector<Vec2>& grid, int nu, int nv) {
  const auto at = [&](int i, int j) -> const Vec2& {
    return grid[static_cast<std::size_t>(j * (nu + 1) + i)];
  };
  double h_min = std::numeric_limits<double>::infinity();
  for (int j = 0; j <= nv; ++j) {
    for (int i = 0; i <= nu; ++i) {
      if (i < nu) h_min = std::min(h_min, (at(i + 1, j) - at(i, j)).norm());
      if (j < nv) h_min = std::min(h_min, (at(i, j + 1) - at(i, j)).norm());
    }
  }
  return h_min;
}

/// Each block checked (cell counts, corners, material, in that order) and mapped.
MappedBlocks map_blocks(const std::vector<MeshBlock>& blocks, const MaterialTable& materials) {
  MappedBlocks mapped;
  for (std::size_t b = 0; b < blocks.size(); ++b) {
    const MeshBlock& block = blocks[b];
    const std::string where = fmt::format("mesh.blocks[{}]", b);
    if (block.cells_u < 1 || block.cells_v < 1) {
      throw Error("{}: cells = [{}, {}] (expected at least one cell each way)", where,
                  block.cells_u, block.cells_v);
    }
    if (const auto problem = block_corners_problem(block)) {
      throw Error("{}: {}", where, *problem);
    }
    for (const Vec2& corner : block.corners) {
      mapped.extent = std::max(mapped.extent, corner.cwiseAbs().maxCoeff());
    }
    mapped.material.push_back(material_id_of(materials, block.material, where + ".material"));
    mapped.grids.push_back(block_grid(block));
    mapped.h_min = std::min(mapped.h_min,
                            smallest_grid_edge(mapped.grids.back(), block.cells_u, block.cells_v));
  }
  return mapped;
}

/// Two block nodes closer than this are one node. A degenerate block (zero-length edge)
/// leaves no length scale: fall back to round-off of the coordinates; validate_mesh then
/// rejects its elements.
double merge_tolerance(const MappedBlocks& mapped) {
  double tolerance = relative_tolerance * mapped.h_min;
  if (!(tolerance > 0.0)) tolerance = 1e-12 * std::max(mapped.extent, 1.0);
  return tolerance;
}

/// Adds the blocks' nodes to `mesh`: a node coincides with a node of an earlier block,
/// or it is new. Returns each block's grid node → mesh node.
std::vector<std::vector<Index>> merge_block_nodes(Mesh& mesh,
                                                  const std::vector<std::vector<Vec2>>& grids,
                                                  double tolerance) {
  std::vector<int> first_block;  // block that created each mesh node
  std::vector<std::vector<Index>> block_nodes(grids.size());
  PointLocator locator(tolerance);
  for (std::size_t b = 0; b < grids.size(); ++b) {
    const int block_index = static_cast<int>(b);
    for (const Vec2& p : grids[b]) {
      Index id = locator.find(p, mesh.nodes, [&](Index m) {
        return first_block[static_cast<std::size_t>(m)] != block_index;
      });
      if (id < 0) {
        id = mesh.node_count();
        mesh.nodes.push_back(p);
        first_block.push_back(block_index);
        locator.insert(p, id);
      }
      block_nodes[b].push_back(id);
    }
  }
  return block_nodes;
}

/// Whether `p` lies within `tolerance` of an edge of `block`.
bool on_block_edge(const Vec2& p, const MeshBlock& block, double tolerance) {
  const auto& q = block.corners;
  for (std::size_t k = 0; k < 4; ++k) {
    if (distance_to_segment(p, q[k], q[(k + 1) % 4]) <= tolerance) return true;
  }
  return false;
}

/// Throws when node `id` at `p`, on the perimeter of block b, lies on an edge of another
/// block that does not have it among its nodes (`sorted_nodes`: each block's mesh nodes,
/// sorted).
void check_perimeter_node(const std::vector<MeshBlock>& blocks, std::size_t b, const Vec2& p,
                          Index id, const std::vector<std::vector<Index>>& sorted_nodes,
                          double tolerance) {
  for (std::size_t a = 0; a < blocks.size(); ++a) {
    if (a == b) continue;
    if (on_block_edge(p, blocks[a], tolerance) &&
        !std::binary_search(sorted_nodes[a].begin(), sorted_nodes[a].end(), id)) {
      throw Error(
          "mesh.blocks[{}] and mesh.blocks[{}]: hanging node at ({}, {}): a node of "
          "block {} lies on an edge of block {} that has no node there (blocks "
          "sharing an edge need the same number of cells along it)",
          std::min(a, b), std::max(a, b), p.x(), p.y(), b, a);
    }
  }
}

/// Hanging nodes: a node on the perimeter of block b that lies on an edge of block a
/// must be a node of block a too, otherwise the two blocks do not share that edge's
/// nodes (different cell counts along it) and the mesh is not conforming.
void check_no_hanging_nodes(const std::vector<MeshBlock>& blocks,
                            const std::vector<std::vector<Vec2>>& grids,
                            const std::vector<std::vector<Index>>& block_nodes, double tolerance) {
  std::vector<std::vector<Index>> sorted_nodes = block_nodes;
  for (auto& ids : sorted_nodes) std::sort(ids.begin(), ids.end());
  for (std::size_t b = 0; b < blocks.size(); ++b) {
    const int nu = blocks[b].cells_u;
    const int nv = blocks[b].cells_v;
    for (int j = 0; j <= nv; ++j) {
      for (int i = 0; i <= nu; ++i) {
        if (i != 0 && i != nu && j != 0 && j != nv) continue;
        const auto g = static_cast<std::size_t>(j * (nu + 1) + i);
        check_perimeter_node(blocks, b, grids[b][g], block_nodes[b][g], sorted_nodes, tolerance);
      }
    }
  }
}

/// Appends each block's cells as elements of its material, blocks in order.
void append_block_elements(Mesh& mesh, const std::vector<MeshBlock>& blocks,
                           const std::vector<std::vector<Index>>& block_nodes,
                           const std::vector<std::int32_t>& block_material) {
  for (std::size_t b = 0; b < blocks.size(); ++b) {
    const int nu = blocks[b].cells_u;
    const auto& ids = block_nodes[b];
    append_grid_elements(
        mesh, nu, blocks[b].cells_v,
        [&](int i, int j) { return ids[static_cast<std::size_t>(j * (nu + 1) + i)]; },
        block_material[b]);
  }
}

}  // namespace

std::optional<std::string> block_corners_problem(const MeshBlock& block) {
  const auto& p = block.corners;
  for (const Vec2& corner : p) {
    if (!corner.allFinite()) return std::string("a corner is not a finite point");
  }
  const double twice_area =
      cross(p[0], p[1]) + cross(p[1], p[2]) + cross(p[2], p[3]) + cross(p[3], p[0]);
  if (!(twice_area > 0.0)) {
    return fmt::format(
        "corners {} {} {} {} are not counter-clockwise (signed area {} m²: clockwise or "
        "degenerate); list them counter-clockwise",
        point_text(p[0]), point_text(p[1]), point_text(p[2]), point_text(p[3]), 0.5 * twice_area);
  }
  // The bilinear map of a non-convex quadrilateral folds over itself.
  for (std::size_t i = 0; i < 4; ++i) {
    const Vec2 in = p[i] - p[(i + 3) % 4];
    const Vec2 out = p[(i + 1) % 4] - p[i];
    if (!(cross(in, out) > 0.0)) {
      return fmt::format("the quadrilateral is not convex at corner {} {}", i, point_text(p[i]));
    }
  }
  return std::nullopt;
}

std::optional<std::string> shared_edge_mismatch(const MeshBlock& a, const MeshBlock& b) {
  for (int side_a = 0; side_a < 4; ++side_a) {
    const auto nodes_a = edge_nodes(a, side_a);
    const Vec2 p = nodes_a.front();
    const Vec2 q = nodes_a.back();
    const double length = (q - p).norm();
    const Vec2 t = (q - p) / length;
    const double spacing_a = length / static_cast<double>(nodes_a.size() - 1);
    for (int side_b = 0; side_b < 4; ++side_b) {
      const auto nodes_b = edge_nodes(b, side_b);
      const double spacing_b =
          (nodes_b.back() - nodes_b.front()).norm() / static_cast<double>(nodes_b.size() - 1);
      const double tol = 1e-6 * std::min(spacing_a, spacing_b);
      auto off_line = [&](const Vec2& r) {
        const Vec2 d = r - p;
        return std::abs(d.x() * t.y() - d.y() * t.x()) > tol;
      };
      if (off_line(nodes_b.front()) || off_line(nodes_b.back())) continue;
      const double s0 = (nodes_b.front() - p).dot(t);
      const double s1 = (nodes_b.back() - p).dot(t);
      const double lo = std::max(0.0, std::min(s0, s1));
      const double hi = std::min(length, std::max(s0, s1));
      if (hi - lo <= tol) continue;  // collinear but not overlapping, or touching at a point
      auto matched = [&](const std::vector<Vec2>& from, const std::vector<Vec2>& to) {
        for (const Vec2& r : from) {
          const double s = (r - p).dot(t);
          if (s < lo - tol || s > hi + tol) continue;
          const bool found = std::any_of(to.begin(), to.end(),
                                         [&](const Vec2& u) { return (u - r).norm() <= tol; });
          if (!found) return false;
        }
        return true;
      };
      if (!matched(nodes_a, nodes_b) || !matched(nodes_b, nodes_a)) {
        return fmt::format("from {} to {} (node spacing {:.6g} m here, {:.6g} m there)",
                           point_text(p + lo * t), point_text(p + hi * t), spacing_a, spacing_b);
      }
    }
  }
  return std::nullopt;
}

Mesh generate_profile_mesh(const MeshSpec& spec, std::int32_t material_id) {
  const double h = spec.element_size;
  const auto& surface = spec.surface;
  if (!(h > 0.0) || !std::isfinite(h)) {
    throw Error("mesh.element_size = {} is not admissible (expected > 0 m)", h);
  }
  if (surface.size() < 2) {
    throw Error("mesh.surface has {} point(s) (expected at least 2, from the wall x = 0)",
                surface.size());
  }
  for (std::size_t k = 0; k < surface.size(); ++k) {
    const Vec2& p = surface[k];
    if (!p.allFinite()) throw Error("mesh.surface[{}] is not a finite point", k);
    if (k == 0 && p.x() != 0.0) {
      throw Error("mesh.surface[0] = [{}, {}] (the surface starts at the wall x = 0)", p.x(),
                  p.y());
    }
    if (k > 0 && !(p.x() > surface[k - 1].x())) {
      throw Error("mesh.surface[{}]: x = {} is not greater than the previous point's x = {}", k,
                  p.x(), surface[k - 1].x());
    }
    if (!(p.y() > 0.0)) {
      throw Error("mesh.surface[{}]: y = {} is not above the base y = 0", k, p.y());
    }
  }

  double top_max = 0.0;
  for (const auto& p : surface) top_max = std::max(top_max, p.y());
  const double requested = (surface.back().x() / h) * (top_max / h);
  if (!(requested <= max_generated_elements)) {
    throw Error(
        "mesh.element_size = {} m asks for about {:.3g} elements over this {} m × {} m profile, "
        "more than the {:g} the mesher builds",
        h, requested, surface.back().x(), top_max, max_generated_elements);
  }

  // Node columns: every surface segment gets its own equal columns, so each surface
  // point is a column and the surface is followed exactly.
  std::vector<double> column_x{surface[0].x()};
  std::vector<double> column_top{surface[0].y()};
  for (std::size_t k = 0; k + 1 < surface.size(); ++k) {
    const Vec2& a = surface[k];
    const Vec2& b = surface[k + 1];
    const int cells = std::max(1, static_cast<int>(std::lround((b.x() - a.x()) / h)));
    for (int c = 1; c <= cells; ++c) {
      // Multiply before dividing, so whole-metre geometry gives exact coordinates.
      column_x.push_back(c == cells ? b.x() : a.x() + (b.x() - a.x()) * c / cells);
      column_top.push_back(c == cells ? b.y() : a.y() + (b.y() - a.y()) * c / cells);
    }
  }
  const int columns = static_cast<int>(column_x.size()) - 1;
  const int rows = std::max(1, static_cast<int>(std::lround(top_max / h)));

  Mesh mesh;
  mesh.element_type = spec.element_type;
  mesh.nodes.reserve(static_cast<std::size_t>((columns + 1) * (rows + 1)));
  for (int j = 0; j <= rows; ++j) {
    for (int i = 0; i <= columns; ++i) {
      const auto col = static_cast<std::size_t>(i);
      mesh.nodes.emplace_back(column_x[col], column_top[col] * j / rows);
    }
  }
  append_grid_elements(
      mesh, columns, rows, [&](int i, int j) { return Index{j} * (columns + 1) + i; }, material_id);
  add_boundary_node_sets(mesh, relative_tolerance * smallest_edge(mesh));
  return mesh;
}

Mesh generate_block_mesh(const MeshSpec& spec, const MaterialTable& materials) {
  const auto& blocks = spec.blocks;
  if (blocks.empty()) throw Error("mesh.blocks: no blocks given");
  double requested = 0.0;
  for (const MeshBlock& block : blocks) {
    requested += static_cast<double>(block.cells_u) * static_cast<double>(block.cells_v);
  }
  if (requested > max_generated_elements) {
    throw Error(
        "mesh.blocks: the cells of the {} block(s) make {:.3g} elements, more than the "
        "{:g} the mesher builds",
        blocks.size(), requested, max_generated_elements);
  }
  const MappedBlocks mapped = map_blocks(blocks, materials);
  const double tolerance = merge_tolerance(mapped);
  Mesh mesh;
  mesh.element_type = spec.element_type;
  const auto block_nodes = merge_block_nodes(mesh, mapped.grids, tolerance);
  check_no_hanging_nodes(blocks, mapped.grids, block_nodes, tolerance);
  append_block_elements(mesh, blocks, block_nodes, mapped.material);
  add_boundary_node_sets(mesh, tolerance);
  return mesh;
}

Mesh build_mesh(const Case& c) {
  const MeshSpec& spec = c.mesh;
  const std::string case_source = c.file.empty() ? std::string("case") : c.file.string();
  std::string source = case_source;
  Mesh mesh;
  switch (spec.generator) {
    case MeshGenerator::profile:
    case MeshGenerator::blocks:
      // The generators name the case-file key at fault; prefix the case file.
      try {
        mesh = spec.generator == MeshGenerator::profile
                   ? generate_profile_mesh(
                         spec, material_id_of(c.materials, spec.material, "mesh.material"))
                   : generate_block_mesh(spec, c.materials);
      } catch (const Error& error) {
        throw Error("{}: {}", case_source, error.what());
      }
      break;
    case MeshGenerator::gmsh:
    case MeshGenerator::opensees: {
      std::filesystem::path path = spec.file();
      if (path.is_relative()) path = c.file.parent_path() / path;
      source = path.string();
      mesh =
          spec.generator == MeshGenerator::gmsh
              ? read_gmsh(path, spec.element_type, c.materials)
              : read_opensees_mesh(path, spec.opensees_materials, spec.ignore_elements, c.materials)
                    .mesh;
      break;
    }
  }
  const bool from_gmsh = spec.generator == MeshGenerator::gmsh;
  check_boundary_names(mesh, c.fem.geostatic_boundaries, "fem.geostatic.boundaries", source,
                       from_gmsh);
  check_boundary_names(mesh, c.fem.failure_boundaries, "fem.failure.boundaries", source, from_gmsh);
  validate_mesh(mesh, source, c.materials.size());
  check_body_in_grid(mesh, c.mpm, case_source, source);
  return mesh;
}

}  // namespace slide
