#include "fem/fem_model.hpp"

#include <algorithm>
#include <limits>
#include <string>

#include "common/base/error.hpp"

namespace slide::fem {

FemState make_rest_state(const FemModel& model) {
  FemState state;
  // The hourglass forces exist for one-point quads only (resize_rows leaves an unused,
  // empty field empty).
  if (model.hourglass) {
    state.hourglass_force.assign(static_cast<std::size_t>(model.element_count()), Vec2::Zero());
  }
  if (model.fluid.active()) {  // the pore-pressure ratio's references (fe_fields.hpp)
    state.static_pore_pressure.assign(static_cast<std::size_t>(model.node_count()), 0.0);
    state.element_pore_pressure.assign(static_cast<std::size_t>(model.element_count()), 0.0);
    const auto points = static_cast<std::size_t>(model.gauss_count());
    state.initial_vertical_effective_stress.assign(points, 0.0);
    state.initial_mean_effective_stress.assign(points, 0.0);
    state.max_pore_pressure_ratio.assign(points, 0.0);
  }
  state.surface_stress.per_point = surfaces_needed(model.materials, Phase::fem);
  resize_rows(fe_fields, state, RowKind::node, static_cast<std::size_t>(model.node_count()));
  resize_rows(fe_fields, state, RowKind::element, static_cast<std::size_t>(model.element_count()));
  resize_rows(fe_fields, state, RowKind::gauss_point,
              static_cast<std::size_t>(model.gauss_count()));
  state.yielded.assign(static_cast<std::size_t>(model.gauss_count()), 0);
  return state;
}

std::vector<Vec2> current_coordinates(const FemModel& model, const FemState& state) {
  std::vector<Vec2> x;
  update_coordinates(model, state, x);
  return x;
}

void update_coordinates(const FemModel& model, const FemState& state, std::vector<Vec2>& x) {
  x.resize(model.mesh.nodes.size());
  for (std::size_t n = 0; n < x.size(); ++n) x[n] = model.mesh.nodes[n] + state.displacement[n];
}

NodalConstraints make_constraints(const Mesh& mesh, const BoundaryTable& table,
                                  std::string_view where) {
  for (const auto& [name, condition] : table) {
    if (mesh.find_node_set(name) == nullptr) {
      std::string known;
      for (const auto& set : mesh.node_sets) known += (known.empty() ? "" : ", ") + set.name;
      throw Error("{}: boundary \"{}\" is not a node set of the mesh (node sets: {})", where, name,
                  known.empty() ? "none" : known);
    }
  }
  const auto n_nodes = static_cast<std::size_t>(mesh.node_count());
  std::vector<std::vector<NodalConstraint>> per_node(n_nodes);
  for (const auto& set : mesh.node_sets) {
    const auto found = table.find(set.name);
    if (found == table.end() || found->second == BoundaryCondition::free) continue;
    for (Index node : set.nodes) {
      per_node[static_cast<std::size_t>(node)].push_back({found->second, set.normal});
    }
  }
  NodalConstraints result;
  result.offsets.assign(n_nodes + 1, 0);
  for (std::size_t n = 0; n < n_nodes; ++n) {
    result.constraints.insert(result.constraints.end(), per_node[n].begin(), per_node[n].end());
    result.offsets[n + 1] = static_cast<Index>(result.constraints.size());
  }
  return result;
}

std::vector<BoundaryCondition> node_set_conditions(const Mesh& mesh, const BoundaryTable& table) {
  std::vector<BoundaryCondition> conditions;
  for (const auto& set : mesh.node_sets) {
    const auto found = table.find(set.name);
    conditions.push_back(found == table.end() ? BoundaryCondition::free : found->second);
  }
  return conditions;
}

}  // namespace slide::fem
