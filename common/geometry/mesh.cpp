#include "common/geometry/mesh.hpp"

#include "common/base/error.hpp"

namespace slide {

std::string_view to_string(BoundaryCondition condition) {
  switch (condition) {
    case BoundaryCondition::free:
      return "free";
    case BoundaryCondition::roller:
      return "roller";
    case BoundaryCondition::fixed:
      return "fixed";
    case BoundaryCondition::friction:
      return "friction";
  }
  return "unknown";
}

BoundaryCondition parse_boundary_condition(std::string_view text, std::string_view where) {
  for (auto c : {BoundaryCondition::free, BoundaryCondition::roller, BoundaryCondition::fixed,
                 BoundaryCondition::friction}) {
    if (text == to_string(c)) return c;
  }
  throw Error(
      "{}: unknown boundary condition \"{}\" (expected \"free\", \"roller\", \"fixed\" or "
      "\"friction\")",
      where, text);
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

}  // namespace slide
