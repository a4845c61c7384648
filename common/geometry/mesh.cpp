#include "common/geometry/mesh.hpp"

#include <algorithm>
#include <cmath>
#include <span>

#include "common/base/error.hpp"
#include "common/base/names.hpp"

namespace slide {

namespace {

constexpr std::array<Named<BoundaryCondition>, 4> boundary_condition_names{{
    {"free", BoundaryCondition::free},
    {"roller", BoundaryCondition::roller},
    {"fixed", BoundaryCondition::fixed},
    {"friction", BoundaryCondition::friction},
}};

}  // namespace

std::string_view to_string(BoundaryCondition condition) {
  return name_of(boundary_condition_names, condition);
}

BoundaryCondition parse_boundary_condition(std::string_view text, std::string_view where) {
  return parse_name(boundary_condition_names, text, where, "boundary condition");
}

ElementNodes Mesh::element_nodes(Index e, std::span<const Vec2> coordinates) const {
  ElementNodes x = ElementNodes::Zero();
  const auto nodes_of_e = element(e);
  for (std::size_t k = 0; k < nodes_of_e.size(); ++k) {
    x.row(static_cast<Eigen::Index>(k)) =
        coordinates[static_cast<std::size_t>(nodes_of_e[k])].transpose();
  }
  return x;
}

const NodeSet* Mesh::find_node_set(std::string_view name) const {
  for (const auto& set : node_sets) {
    if (set.name == name) return &set;
  }
  return nullptr;
}

namespace {

/// Node sets must be straight within this share of the mesh's extent (at least 1 m).
constexpr double straightness_tolerance = 1e-6;

/// The mesh is not empty, its connectivity has the size of its elements, its nodes are
/// finite points.
void check_mesh_sizes(const Mesh& mesh, std::string_view source) {
  const int n = mesh.nodes_per_element();
  const Index element_count = mesh.element_count();
  if (element_count == 0) throw Error("{}: the mesh has no elements", source);
  if (mesh.connectivity.size() != static_cast<std::size_t>(element_count * n)) {
    throw Error("{}: connectivity has {} entries for {} elements of {} nodes", source,
                mesh.connectivity.size(), element_count, n);
  }
  for (Index i = 0; i < mesh.node_count(); ++i) {
    const Vec2& p = mesh.nodes[static_cast<std::size_t>(i)];
    if (!p.allFinite()) throw Error("{}: node {} has a coordinate that is not finite", source, i);
  }
}

/// The mean of an element's `n` node coordinates `x`, where its messages place it.
Vec2 element_centre(const ElementNodes& x, int n) {
  Vec2 centre = Vec2::Zero();
  for (int k = 0; k < n; ++k) centre += x.row(k).transpose() / n;
  return centre;
}

/// Element `e` (nodes `nodes` at `x`) is neither inverted nor of zero area: a triangle's
/// signed area, a quadrangle's det J at each corner, above a fraction of its size.
void check_element_not_inverted(ElementShape shape, Index e, std::span<const Index> nodes,
                                const ElementNodes& x, const Vec2& centre,
                                std::string_view source) {
  const double threshold = degenerate_jacobian_fraction * longest_edge_squared(shape, x);
  if (shape == ElementShape::tri3) {
    const double area = element_area(shape, x);
    if (area <= threshold) {
      throw Error(
          "{}: element {} at ({}, {}) is inverted or has zero area (signed area {} "
          "m²)",
          source, e, centre.x(), centre.y(), area);
    }
    return;
  }
  const auto corners = reference_corners(shape);
  for (std::size_t k = 0; k < corners.size(); ++k) {
    const double det = jacobian(shape, x, corners[k]).determinant();
    if (det <= 0.25 * threshold) {
      throw Error(
          "{}: element {} at ({}, {}) is inverted or has zero area: det J = {} at its "
          "corner {} (node {} at ({}, {}))",
          source, e, centre.x(), centre.y(), det, k, nodes[k], x(static_cast<int>(k), 0),
          x(static_cast<int>(k), 1));
    }
  }
}

/// Checks each element in turn (node indices in range, material id in range, not
/// inverted); returns which nodes the elements reference.
std::vector<bool> check_elements(const Mesh& mesh, std::string_view source,
                                 std::size_t material_count) {
  const Index node_count = mesh.node_count();
  std::vector<bool> referenced(static_cast<std::size_t>(node_count), false);
  for (Index e = 0; e < mesh.element_count(); ++e) {
    const auto nodes = mesh.element(e);
    for (const Index node : nodes) {
      if (node < 0 || node >= node_count) {
        throw Error("{}: element {} refers to node {}, out of range (the mesh has {} nodes)",
                    source, e, node, node_count);
      }
      referenced[static_cast<std::size_t>(node)] = true;
    }
    const ElementNodes x = mesh.element_nodes(e, mesh.nodes);
    const Vec2 centre = element_centre(x, mesh.nodes_per_element());
    const auto material = mesh.material_id[static_cast<std::size_t>(e)];
    if (material < 0 || static_cast<std::size_t>(material) >= material_count) {
      throw Error(
          "{}: element {} at ({}, {}) has material id {}, out of range (the case has {} "
          "materials)",
          source, e, centre.x(), centre.y(), material, material_count);
    }
    check_element_not_inverted(mesh.shape(), e, nodes, x, centre, source);
  }
  return referenced;
}

/// Every node is a node of an element (`referenced`).
void check_nodes_referenced(const Mesh& mesh, const std::vector<bool>& referenced,
                            std::string_view source) {
  for (Index i = 0; i < mesh.node_count(); ++i) {
    if (!referenced[static_cast<std::size_t>(i)]) {
      const Vec2& p = mesh.nodes[static_cast<std::size_t>(i)];
      throw Error("{}: node {} at ({}, {}) belongs to no element", source, i, p.x(), p.y());
    }
  }
}

/// Node set `set`: not empty, in range, one outward unit normal, straight (every node
/// within `straightness` of the line through the first node perpendicular to the normal).
void check_node_set(const Mesh& mesh, const NodeSet& set, double straightness,
                    std::string_view source) {
  const Index node_count = mesh.node_count();
  if (set.nodes.empty()) throw Error("{}: node set '{}' is empty", source, set.name);
  for (const Index node : set.nodes) {
    if (node < 0 || node >= node_count) {
      throw Error("{}: node set '{}' refers to node {}, out of range (the mesh has {} nodes)",
                  source, set.name, node, node_count);
    }
  }
  if (std::abs(set.normal.norm() - 1.0) > 1e-9) {
    throw Error("{}: node set '{}' has a normal ({}, {}) that is not a unit vector", source,
                set.name, set.normal.x(), set.normal.y());
  }
  const Vec2& origin = mesh.nodes[static_cast<std::size_t>(set.nodes.front())];
  for (const Index node : set.nodes) {
    const Vec2& p = mesh.nodes[static_cast<std::size_t>(node)];
    if (std::abs((p - origin).dot(set.normal)) > straightness) {
      throw Error(
          "{}: node set '{}' is not straight: node {} at ({}, {}) is {} m off the line "
          "through node {} normal to ({}, {})",
          source, set.name, node, p.x(), p.y(), std::abs((p - origin).dot(set.normal)),
          set.nodes.front(), set.normal.x(), set.normal.y());
    }
  }
}

/// Every node set passes check_node_set, with a straightness tolerance relative to the
/// mesh's extent.
void check_node_sets(const Mesh& mesh, std::string_view source) {
  double extent = 0.0;
  for (const Vec2& p : mesh.nodes) extent = std::max(extent, p.cwiseAbs().maxCoeff());
  const double straightness = straightness_tolerance * std::max(extent, 1.0);
  for (const auto& set : mesh.node_sets) check_node_set(mesh, set, straightness, source);
}

}  // namespace

// The checks run in this order, and each in mesh order: the first fault is reported.
void validate_mesh(const Mesh& mesh, std::string_view source, std::size_t material_count) {
  check_mesh_sizes(mesh, source);
  const std::vector<bool> referenced = check_elements(mesh, source, material_count);
  check_nodes_referenced(mesh, referenced, source);
  check_node_sets(mesh, source);
}

}  // namespace slide
