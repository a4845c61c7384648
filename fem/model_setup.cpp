#include "fem/model_setup.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "common/base/error.hpp"
#include "fem/element_kernels.hpp"
#include "fem/pore_fluid.hpp"

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

/// Every element's material is one of the model's.
void check_material_ids(const FemModel& model) {
  const auto& ids = model.mesh.material_id;
  for (std::size_t e = 0; e < ids.size(); ++e) {
    if (ids[e] < 0 || static_cast<std::size_t>(ids[e]) >= model.materials.size()) {
      throw Error("mesh: element {} has material id {} but there are {} materials", e, ids[e],
                  model.materials.size());
    }
  }
}

/// Per element ρ and the wave speed of the Courant step: the material's, or with pore
/// water a saturated element's undrained V_p,u = sqrt((M + K_f/n)/ρ_sat) and a porous
/// element above the water table's dry ρ_sat − n ρ_w (docs/method.md §10).
void compute_densities(FemModel& model, const std::optional<WaterSpec>& water) {
  const Mesh& m = model.mesh;
  const auto n_elements = static_cast<std::size_t>(m.element_count());
  model.elements.density.resize(n_elements);
  model.elements.wave_speed.resize(n_elements);
  model.elements.skeleton_wave_speed.resize(n_elements);
  const Vec2 centre = reference_centre(m.shape());
  for (std::size_t e = 0; e < n_elements; ++e) {
    const auto ei = static_cast<Index>(e);
    const Material& material = model.material_of(ei);
    model.elements.density[e] = material.density;
    model.elements.wave_speed[e] =
        model.elastic.wave_speed[static_cast<std::size_t>(m.material_id[e])];
    model.elements.skeleton_wave_speed[e] = model.elements.wave_speed[e];
    if (!water || !material.saturable()) continue;
    const Vec2 x = map_to_physical(m.shape(), m.element_nodes(ei, m.nodes), centre);
    if (model.fluid.depth(x) > 0.0) {
      const double undrained = material.p_wave_modulus() + water->bulk_modulus / material.porosity;
      model.elements.wave_speed[e] = std::sqrt(undrained / material.density);
    } else {
      model.elements.density[e] = material.density - material.porosity * water->density;
      if (!(model.elements.density[e] > 0.0)) {
        throw Error(
            "material \"{}\": its dry density ρ_sat − n ρ_w = {} − {}·{} is not positive "
            "(density is the saturated density of a porous material)",
            material.name, material.density, material.porosity, water->density);
      }
      model.elements.wave_speed[e] =
          std::sqrt(material.p_wave_modulus() / model.elements.density[e]);
      model.elements.skeleton_wave_speed[e] = model.elements.wave_speed[e];
    }
  }
}

/// Per element det J at the centre, V_0^e and m_e; per node the lumped mass and m_I g.
void compute_masses(FemModel& model) {
  const Mesh& m = model.mesh;
  const auto n_elements = static_cast<std::size_t>(m.element_count());
  model.elements.centre_det_reference.resize(n_elements);
  model.elements.volume_reference.resize(n_elements);
  model.elements.mass.resize(n_elements);
  model.lumped.mass.assign(static_cast<std::size_t>(m.node_count()), 0.0);
  const Vec2 centre = reference_centre(m.shape());
  for (std::size_t e = 0; e < n_elements; ++e) {
    const auto ei = static_cast<Index>(e);
    const ElementNodes x = m.element_nodes(ei, m.nodes);
    const double density = model.elements.density[e];
    model.elements.centre_det_reference[e] = jacobian(m.shape(), x, centre).determinant();
    model.elements.volume_reference[e] = element_area(m.shape(), x);
    model.elements.mass[e] = density * model.elements.volume_reference[e];
    add_element_mass(m, ei, density, model.lumped.mass);
  }
  model.lumped.external_force.resize(model.lumped.mass.size());
  for (std::size_t n = 0; n < model.lumped.mass.size(); ++n) {
    if (!(model.lumped.mass[n] > 0.0)) throw Error("mesh: node {} belongs to no element", n);
    model.lumped.external_force[n] = model.lumped.mass[n] * model.gravity;
  }
}

VerticalExtent vertical_extent(const std::vector<Vec2>& nodes) {
  VerticalExtent extent;
  double y_max = -std::numeric_limits<double>::infinity();
  extent.y_min = std::numeric_limits<double>::infinity();
  for (const Vec2& x : nodes) {
    extent.y_min = std::min(extent.y_min, x.y());
    y_max = std::max(y_max, x.y());
  }
  extent.height = y_max - extent.y_min;
  return extent;
}

}  // namespace

FemModel make_model(Mesh mesh, MaterialTable materials, Kinematics kinematics,
                    double hourglass_coefficient, const Vec2& gravity,
                    const std::optional<WaterSpec>& water) {
  FemModel model;
  model.gravity = gravity;
  model.mesh = std::move(mesh);
  model.materials = std::move(materials);
  model.kinematics = kinematics;
  model.hourglass_coefficient = hourglass_coefficient;
  const ElementType type = model.mesh.element_type;
  model.nodes_per_element = model.mesh.nodes_per_element();
  const auto rule = quadrature_rule(type);
  model.hourglass = type == ElementType::quad4_1gp;
  for (const auto& point : rule) {
    model.rule.local.push_back(point.xi);
    model.rule.weight.push_back(point.weight);
  }
  for (const auto& material : model.materials) {
    model.elastic.matrix.push_back(plane_strain_elasticity(material));
    model.elastic.wave_speed.push_back(material.p_wave_speed());
  }
  check_material_ids(model);
  const Index inverted = compute_geometry(model, model.mesh.nodes, model.reference);
  if (inverted >= 0) {
    throw Error(
        "mesh: element {} is inverted or degenerate (det J ≤ 0 in the reference "
        "configuration)",
        inverted);
  }
  if (water) {
    model.fluid.density = water->density;
    model.fluid.bulk_modulus = water->bulk_modulus;
    model.fluid.tension_limit = water->tension_limit;
    model.fluid.level_point = Vec2(0.0, water->level);
    model.fluid.profile = water->profile;
    if (water->reservoir) model.fluid.reservoir_point = Vec2(0.0, *water->reservoir);
    model.fluid.reservoir_extent = Vec2(water->reservoir_x_min, water->reservoir_x_max);
    model.fluid.gravity = gravity;
  }
  compute_densities(model, water);
  compute_masses(model);
  if (water) make_pore_fluid(model, water->drained);
  model.extent = vertical_extent(model.mesh.nodes);
  build_node_slots(model);
  return model;
}

}  // namespace slide::fem
