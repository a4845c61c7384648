// A finite element mesh in its reference configuration: nodes, one element type,
// connectivity, material per element and named boundary node sets. The FE phase builds
// it (mesher or Gmsh import), checkpoints carry it, the transfer reads it back.
#pragma once

#include <cstddef>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "common/base/types.hpp"
#include "common/geometry/element.hpp"

namespace slide {

/// What a boundary does to the velocity of its nodes (docs/method.md §3, §5).
enum class BoundaryCondition {
  free,      ///< nothing
  roller,    ///< zero normal velocity, free tangential sliding
  fixed,     ///< zero velocity
  friction,  ///< zero normal velocity, Coulomb stick/slip with coefficient μ tangentially
};
std::string_view to_string(BoundaryCondition condition);
BoundaryCondition parse_boundary_condition(std::string_view text, std::string_view where);

/// A boundary name ("left", "right", "base", "top" or a Gmsh physical group) → condition.
using BoundaryTable = std::map<std::string, BoundaryCondition>;

/// A named set of boundary nodes ("left", "right", "base", or a Gmsh physical group),
/// straight, with its outward unit normal.
struct NodeSet {
  std::string name;
  std::vector<Index> nodes;
  Vec2 normal = Vec2::Zero();
};

struct Mesh {
  ElementType element_type = ElementType::quad4_1gp;
  std::vector<Vec2> nodes;                ///< reference coordinates X
  std::vector<Index> connectivity;        ///< element-major, nodes_per_element() entries each
  std::vector<std::int32_t> material_id;  ///< one per element
  std::vector<NodeSet> node_sets;

  ElementShape shape() const { return shape_of(element_type); }
  int nodes_per_element() const { return slide::nodes_per_element(element_type); }
  Index element_count() const { return static_cast<Index>(material_id.size()); }
  Index node_count() const { return static_cast<Index>(nodes.size()); }
  /// Node indices of element e.
  std::span<const Index> element(Index e) const {
    return {connectivity.data() + e * nodes_per_element(),
            static_cast<std::size_t>(nodes_per_element())};
  }
  /// Coordinates of element e's nodes taken from `coordinates` (reference or current).
  ElementNodes element_nodes(Index e, std::span<const Vec2> coordinates) const;
  /// The node set called `name`, or nullptr.
  const NodeSet* find_node_set(std::string_view name) const;
};

/// Throws Error naming `source` and the first offending element or node: inverted or
/// zero-area elements (det J ≤ 0 at a corner), nodes no element references, node sets
/// that are empty or not straight, material ids out of range.
void validate_mesh(const Mesh& mesh, std::string_view source, std::size_t material_count);

}  // namespace slide
