#include "fem/fem_model.hpp"

#include <algorithm>
#include <limits>
#include <string>

#include "common/base/error.hpp"
#include "fem/element_kernels.hpp"

namespace slide::fem {

namespace {

void add_element_mass(const Mesh& mesh, Index e, double density, std::vector<double>& nodal_mass) {
  const ShapeValues mass =
      lumped_element_mass(mesh.shape(), mesh.element_nodes(e, mesh.nodes), density);
  const auto nodes = mesh.element(e);
  for (std::size_t k = 0; k < nodes.size(); ++k) {
    nodal_mass[static_cast<std::size_t>(nodes[k])] += mass[k];
  }
}

void build_node_slots(FemModel& model) {
  const auto n_nodes = static_cast<std::size_t>(model.node_count());
  const auto& connectivity = model.mesh.connectivity;
  model.adjacency.offsets.assign(n_nodes + 1, 0);
  for (Index node : connectivity) ++model.adjacency.offsets[static_cast<std::size_t>(node) + 1];
  for (std::size_t n = 0; n < n_nodes; ++n) {
    model.adjacency.offsets[n + 1] += model.adjacency.offsets[n];
  }
  model.adjacency.slots.resize(connectivity.size());
  std::vector<Index> fill(model.adjacency.offsets.begin(), model.adjacency.offsets.end() - 1);
  for (std::size_t slot = 0; slot < connectivity.size(); ++slot) {
    const auto node = static_cast<std::size_t>(connectivity[slot]);
    model.adjacency.slots[static_cast<std::size_t>(fill[node]++)] = static_cast<Index>(slot);
  }
}

}  // namespace

FemModel make_model(Mesh mesh, MaterialTable materials, Kinematics kinematics,
                    double hourglass_coefficient, const Vec2& gravity) {
  FemModel model;
  model.gravity = gravity;
  model.mesh = std::move(mesh);
  model.materials = std::move(materials);
  model.kinematics = kinematics;
  model.hourglass_coefficient = hourglass_coefficient;
  const Mesh& m = model.mesh;
  const ElementType type = m.element_type;
  model.nodes_per_element = m.nodes_per_element();
  const auto rule = quadrature_rule(type);
  model.gauss_per_element = static_cast<int>(rule.size());
  model.hourglass = type == ElementType::quad4_1gp;
  for (const auto& point : rule) {
    model.rule.local.push_back(point.xi);
    model.rule.weight.push_back(point.weight);
  }
  for (const auto& material : model.materials) {
    model.elastic.matrix.push_back(plane_strain_elasticity(material));
    model.elastic.wave_speed.push_back(material.p_wave_speed());
  }

  const auto n_elements = static_cast<std::size_t>(m.element_count());
  for (std::size_t e = 0; e < n_elements; ++e) {
    const auto id = m.material_id[e];
    if (id < 0 || static_cast<std::size_t>(id) >= model.materials.size()) {
      throw Error("mesh: element {} has material id {} but there are {} materials", e, id,
                  model.materials.size());
    }
  }

  const Index inverted = compute_geometry(model, m.nodes, model.reference);
  if (inverted >= 0) {
    throw Error(
        "mesh: element {} is inverted or degenerate (det J ≤ 0 in the reference "
        "configuration)",
        inverted);
  }

  model.elements.centre_det_reference.resize(n_elements);
  model.elements.volume_reference.resize(n_elements);
  model.elements.mass.resize(n_elements);
  model.lumped.mass.assign(static_cast<std::size_t>(m.node_count()), 0.0);
  const Vec2 centre = reference_centre(m.shape());
  for (std::size_t e = 0; e < n_elements; ++e) {
    const auto ei = static_cast<Index>(e);
    const ElementNodes x = m.element_nodes(ei, m.nodes);
    const double density = model.material_of(ei).density;
    model.elements.centre_det_reference[e] = jacobian(m.shape(), x, centre).determinant();
    model.elements.volume_reference[e] = element_area(m.shape(), x);
    model.elements.mass[e] = density * model.elements.volume_reference[e];
    add_element_mass(m, ei, density, model.lumped.mass);
  }
  model.lumped.gravity_force.resize(model.lumped.mass.size());
  for (std::size_t n = 0; n < model.lumped.mass.size(); ++n) {
    if (!(model.lumped.mass[n] > 0.0)) throw Error("mesh: node {} belongs to no element", n);
    model.lumped.gravity_force[n] = model.lumped.mass[n] * model.gravity;
  }

  double y_max = -std::numeric_limits<double>::infinity();
  model.extent.y_min = std::numeric_limits<double>::infinity();
  for (const Vec2& x : m.nodes) {
    model.extent.y_min = std::min(model.extent.y_min, x.y());
    y_max = std::max(y_max, x.y());
  }
  model.extent.height = y_max - model.extent.y_min;
  build_node_slots(model);
  return model;
}

FemState make_rest_state(const FemModel& model) {
  FemState state;
  // The hourglass forces exist for one-point quads only (resize_rows leaves an unused,
  // empty field empty).
  if (model.hourglass) {
    state.hourglass_force.assign(static_cast<std::size_t>(model.element_count()), Vec2::Zero());
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
