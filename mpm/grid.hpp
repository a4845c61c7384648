// The background grid: square cells of size h covering the domain box, and the nodal
// arrays one step needs. The grid carries nothing between steps (docs/method.md §5).
//
// Layout. Cells (cx, cy), 0 ≤ cx < cells_x, 0 ≤ cy < cells_y; nodes (i, j) at
// x0 + (i h, j h). One ring of ghost nodes, i = −1 and i = cells_x + 1 (likewise j),
// surrounds the domain so that the uGIMP support of any particle whose centre lies in
// the domain (domain half-length ≤ h/2) indexes valid nodes: a particle whose domain
// pokes slightly through the base or a wall simply puts a little mass on a ghost node,
// which gets the same velocity constraint as the edge it lies beyond.
//
// Node storage is x-major, column after column (index = (i+1)·rows + (j+1)), and so is
// the cell order particles are sorted in: a contiguous range of sorted particles touches
// a contiguous band of node columns, which is what makes the per-block scatter windows
// of kernels.hpp small and their reduction cheap.
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <vector>

#include "common/base/pair.hpp"
#include "common/base/types.hpp"
#include "common/geometry/mesh.hpp"
#include "common/physics/nodal_update.hpp"

namespace slide::mpm {

/// Sums a particle-to-grid pass accumulates at one node.
struct NodeSums {
  double mass;
  double momentum_x, momentum_y;
  double force_x, force_y;  ///< internal + external (gravity), without reactions
};

/// Sums of volumetric smoothing over the particles of one cell: Σ V_p, Σ V_p tr L_p and
/// Σ V_p p_p (p = −tr σ/3, compression positive: common/physics/constitutive.hpp's mean_stress).
struct CellSums {
  double volume = 0.0;
  double volumetric_rate = 0.0;
  double mean_stress = 0.0;
};

/// A cell's volume-weighted averages of the particles' volumetric rate tr L and mean stress
/// p (compression positive).
struct CellAverages {
  double volumetric_rate = 0.0;
  double mean_stress = 0.0;
};

/// What a grid-to-particle pass reads at one node: the velocity change rate a_i used
/// by FLIP and the end-of-step (Lagrangian) velocity v_i^L.
struct NodeMotion {
  double acceleration_x, acceleration_y;
  double velocity_x, velocity_y;
};

/// Grid edges in the order of `GridGeometry::edge_conditions`.
enum GridEdge { edge_left = 0, edge_right = 1, edge_base = 2, edge_top = 3 };

struct GridGeometry {
  Vec2 origin = Vec2::Zero();  ///< lower-left corner x0
  double cell_size = 1.0;      ///< h
  int cells_x = 0, cells_y = 0;

  /// Builds the grid over [domain_min, domain_max]; the box is extended up and to the
  /// right to a whole number of cells when it is not one already.
  static GridGeometry covering(const Vec2& domain_min, const Vec2& domain_max, double cell_size);

  Vec2 upper_corner() const { return origin + cell_size * Vec2(cells_x, cells_y); }
  int node_columns() const { return cells_x + 3; }
  int node_rows() const { return cells_y + 3; }
  std::size_t node_count() const {
    return static_cast<std::size_t>(node_columns()) * static_cast<std::size_t>(node_rows());
  }
  std::size_t cell_count() const {
    return static_cast<std::size_t>(cells_x) * static_cast<std::size_t>(cells_y);
  }
  /// Storage index of node (i, j), −1 ≤ i ≤ cells_x + 1.
  std::size_t node_index(int i, int j) const {
    return static_cast<std::size_t>(i + 1) * static_cast<std::size_t>(node_rows()) +
           static_cast<std::size_t>(j + 1);
  }
  /// Node column (storage order) of a node index.
  int node_column(std::size_t index) const {
    return static_cast<int>(index / static_cast<std::size_t>(node_rows()));
  }
  Vec2 node_position(std::size_t index) const;
  /// True when a particle centred at x is on the grid: within half a cell of the domain
  /// box, ξ ∈ [−½, cells + ½). Every node of its stencil (uGIMP or linear) then exists
  /// (ghost ring included), and a particle pressed slightly through a wall or the base
  /// stays in play: the ghost nodes beyond a wall carry the wall's constraint, so it
  /// cannot go further than about its own half-size.
  /// Both axes at once (pair.hpp): lane by lane the division and comparisons of
  /// ξ = (x − x0)/h, η likewise.
  bool contains(const Vec2& x) const {
    const Pair xi = (load_pair(x.data()) - load_pair(origin.data())) / cell_size;
    const Pair cells{static_cast<double>(cells_x), static_cast<double>(cells_y)};
    return lanes::all(xi >= -0.5) && lanes::all(xi < cells + 0.5);
  }
  /// x-major cell index of a point on the grid (the half-cell margins count as the
  /// boundary cells).
  std::size_t cell_of(const Vec2& x) const;
};

/// Velocity constraints of the four grid edges (docs/method.md §5): left/right walls, base,
/// top, each free, roller, fixed or friction, with the body's outward normal there.
struct GridBoundaries {
  std::array<NodalConstraint, 4> edge;  ///< indexed by GridEdge
  double friction_coefficient = 0.0;
  /// Shaking (docs/method.md §8): the edges move with the base at this velocity over the
  /// current step, and every constraint acts on the velocity relative to it (a fixed
  /// node follows the base, a frictional one slides on it). `moving` is set for a run
  /// with a base motion, even while the motion is at rest.
  Vec2 frame_velocity = Vec2::Zero();
  bool moving = false;

  /// From the case's "left", "right", "base", "top" entries (missing ones are free).
  static GridBoundaries from(const BoundaryTable& table, double friction_coefficient);

  /// The constraints of node (i, j): those of every edge the node lies on or beyond
  /// (at most two, at a corner). Returns how many were written to `out`.
  int constraints_of(const GridGeometry& grid, int i, int j,
                     std::array<NodalConstraint, 2>& out) const;
};

/// The nodal arrays of one step. Only the node columns some particle touches
/// ([active_begin, active_end)) are written and read in a step.
struct GridState {
  std::vector<NodeSums> sums;      ///< mass, momentum, force (pass 1)
  std::vector<NodeMotion> motion;  ///< a_i and v_i^L after damping and constraints
  /// MUSL: velocity re-projected from the updated particle momenta (constrained).
  std::vector<Vec2> remapped_velocity;
  /// Volumetric smoothing: each cell's averages, at the storage index of the node at its
  /// lower-left corner.
  std::vector<CellAverages> cell_averages;
  int active_begin = 0, active_end = 0;  ///< node columns
  /// Node columns this process owns (all on one process; mpm/domain.hpp on several):
  /// sums over nodes, such as the constraints' work, count only these.
  int own_begin = 0, own_end = std::numeric_limits<int>::max();
  bool parallel = false;  ///< enough work for several threads

  void resize(const GridGeometry& grid);
  std::size_t bytes() const;
};

}  // namespace slide::mpm
