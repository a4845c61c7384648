#include "fem/seismic_boundary.hpp"

#include <algorithm>
#include <cmath>
#include <map>

#include <fmt/format.h>

#include "common/base/error.hpp"
#include "fem/element_kernels.hpp"
#include "fem/geostatic.hpp"
#include "fem/pore_fluid.hpp"

namespace slide::fem {

namespace {

const NodeSet& node_set(const Mesh& mesh, std::string_view name) {
  for (const NodeSet& set : mesh.node_sets) {
    if (set.name == name) return set;
  }
  throw Error("fem.motion: the mesh has no node set \"{}\"", name);
}

/// Each node's share of the length of a straight boundary: half of each neighbouring
/// segment along it.
std::map<Index, double> tributary_lengths(const Mesh& mesh, const NodeSet& set) {
  const Vec2 tangent(-set.normal.y(), set.normal.x());
  std::vector<std::pair<double, Index>> along;
  for (const Index node : set.nodes) {
    along.emplace_back(mesh.nodes[static_cast<std::size_t>(node)].dot(tangent), node);
  }
  std::ranges::sort(along);
  std::map<Index, double> length;
  for (std::size_t i = 0; i < along.size(); ++i) {
    double share = 0.0;
    if (i > 0) share += 0.5 * (along[i].first - along[i - 1].first);
    if (i + 1 < along.size()) share += 0.5 * (along[i + 1].first - along[i].first);
    length[along[i].second] = share;
  }
  return length;
}

/// The first element at a node.
Index element_at(const FemModel& model, Index node) {
  const auto n = static_cast<std::size_t>(node);
  const auto slot = model.adjacency.slots[static_cast<std::size_t>(model.adjacency.offsets[n])];
  return slot / model.nodes_per_element;
}

/// Lysmer dashpots of the soil on a vertical edge: normal ρ V_p L, tangential ρ V_s L,
/// and the horizontal static reaction. ρ and V_p are the element's (ElementConstants):
/// a saturated element's ρ_sat and undrained V_p,u, a porous one's dry ρ above the table.
void make_viscous(const FemModel& model, Index node, double length,
                  const std::vector<Vec2>& reactions, SeismicBoundary& boundary) {
  const Index e = element_at(model, node);
  const auto ei = static_cast<std::size_t>(e);
  const double density = model.elements.density[ei];
  const auto n = static_cast<std::size_t>(node);
  const double shear_speed = std::sqrt(model.material_of(e).shear_modulus() / density);
  boundary.dashpot[n] +=
      Vec2(density * model.elements.wave_speed[ei] * length, density * shear_speed * length);
  boundary.static_force[n].x() += reactions[n].x();
  ++boundary.viscous_side_nodes;
}

}  // namespace

std::vector<Vec2> support_reactions(const FemModel& model, const FemState& state) {
  std::vector<Vec2> element_force(
      static_cast<std::size_t>(model.element_count() * model.nodes_per_element));
  FemState at_rest = state;
  std::ranges::fill(at_rest.velocity, Vec2::Zero());
  compute_element_forces(model, model.reference, at_rest, element_force);
  // With pore water the supports also hold the water's thrust.
  add_pore_pressure_forces(model, model.reference, state.element_pore_pressure, element_force);
  std::vector<Vec2> reactions(static_cast<std::size_t>(model.node_count()));
  for (std::size_t n = 0; n < reactions.size(); ++n) {
    Vec2 force = model.lumped.external_force[n];
    for (auto i = model.adjacency.offsets[n]; i < model.adjacency.offsets[n + 1]; ++i) {
      force += element_force[static_cast<std::size_t>(
          model.adjacency.slots[static_cast<std::size_t>(i)])];
    }
    reactions[n] = -force;
  }
  return reactions;
}

namespace {

/// The base: a compliant one's dashpots and incident forces (and the vertical static
/// reactions, when a vertical motion releases them) on its nodes. Returns which nodes are
/// on the base.
std::vector<std::uint8_t> set_up_base(const FemModel& model, const MotionSpec& spec,
                                      const std::vector<Vec2>& reactions,
                                      SeismicBoundary& boundary) {
  const Mesh& mesh = model.mesh;
  std::vector<std::uint8_t> on_base(static_cast<std::size_t>(model.node_count()), 0);
  if (spec.base != SeismicBase::compliant) {
    for (const Index node : node_set(mesh, "base").nodes)
      on_base[static_cast<std::size_t>(node)] = 1;
    return on_base;
  }
  const double impedance_s = spec.rock_density * spec.rock_shear_wave_speed;
  const double impedance_p = spec.rock_density * spec.rock_p_wave_speed;
  // The incident wave is the motion (incident input) or half of it (outcrop).
  const double incident_factor = spec.input == MotionInput::incident ? 2.0 : 1.0;
  for (const auto& [node, length] : tributary_lengths(mesh, node_set(mesh, "base"))) {
    const auto n = static_cast<std::size_t>(node);
    on_base[n] = 1;
    boundary.dashpot[n].x() = impedance_s * length;
    boundary.incident[n].x() = incident_factor * impedance_s * length;
    if (spec.vertical) {
      boundary.dashpot[n].y() = impedance_p * length;
      boundary.incident[n].y() = incident_factor * impedance_p * length;
      boundary.static_force[n].y() = reactions[n].y();
    }
  }
  return on_base;
}

/// One lateral edge: its nodes by elevation (a rigid base prescribes its nodes: its
/// corners belong to no pair) and each node's tributary length.
struct Side {
  std::map<Index, double> length;
  std::vector<std::pair<double, Index>> nodes;

  Side(const Mesh& mesh, const char* name, const std::vector<std::uint8_t>& on_base, bool rigid)
      : length(tributary_lengths(mesh, node_set(mesh, name))) {
    for (const auto& [node, l] : length) {
      if (rigid && on_base[static_cast<std::size_t>(node)]) continue;
      nodes.emplace_back(mesh.nodes[static_cast<std::size_t>(node)].y(), node);
    }
    std::ranges::sort(nodes);
  }
};

/// The element with both nodes a and b (−1 when there is none).
Index element_with_side(const FemModel& model, Index a, Index b) {
  const auto& adjacency = model.adjacency;
  const auto npe = static_cast<Index>(model.nodes_per_element);
  for (auto i = adjacency.offsets[static_cast<std::size_t>(a)];
       i < adjacency.offsets[static_cast<std::size_t>(a) + 1]; ++i) {
    const Index e = adjacency.slots[static_cast<std::size_t>(i)] / npe;
    const auto nodes = model.mesh.element(e);
    if (std::ranges::find(nodes, b) != nodes.end()) return e;
  }
  return -1;
}

/// boundary.tied_elements: for two consecutive tied pairs (i₁, j₁), (i₂, j₂), the element
/// along i₁ i₂ with the one along j₁ j₂.
void pair_side_elements(const FemModel& model, SeismicBoundary& boundary) {
  for (std::size_t k = 0; k + 1 < boundary.tied.size(); ++k) {
    const Index left = element_with_side(model, boundary.tied[k].first, boundary.tied[k + 1].first);
    const Index right =
        element_with_side(model, boundary.tied[k].second, boundary.tied[k + 1].second);
    if (left >= 0 && right >= 0 && left != right) boundary.tied_elements.emplace_back(left, right);
  }
}

/// Tied sides: nodes at equal elevation (within 1e-6 of the model's height) paired, each
/// pair keeping its static horizontal reactions. Returns which nodes are paired.
std::vector<std::uint8_t> tie_sides(const FemModel& model, const MotionSpec& spec, const Side& left,
                                    const Side& right, const std::vector<Vec2>& reactions,
                                    SeismicBoundary& boundary) {
  boundary.tie_vertical = spec.lateral == LateralBoundary::tied;
  const double tolerance = 1e-6 * std::max(model.extent.height, 1.0);
  std::vector<std::uint8_t> paired(static_cast<std::size_t>(model.node_count()), 0);
  for (const auto& [node, partner] : pair_by_elevation(left.nodes, right.nodes, tolerance)) {
    boundary.tied.emplace_back(node, partner);
    paired[static_cast<std::size_t>(node)] = paired[static_cast<std::size_t>(partner)] = 1;
    for (const Index n : {node, partner}) {
      boundary.static_force[static_cast<std::size_t>(n)].x() +=
          reactions[static_cast<std::size_t>(n)].x();
    }
  }
  pair_side_elements(model, boundary);
  if (boundary.tied.empty()) {
    throw Error(
        "fem.motion.lateral = \"{}\": no node of the left edge is at the elevation of a node "
        "of the right edge",
        to_string(spec.lateral));
  }
  return paired;
}

}  // namespace

SeismicBoundary make_seismic_boundary(const FemModel& model, const MotionSpec& spec,
                                      const GroundMotion& motion,
                                      const std::vector<Vec2>& reactions) {
  const auto n_nodes = static_cast<std::size_t>(model.node_count());
  SeismicBoundary boundary;
  boundary.base = spec.base;
  boundary.motion = &motion;
  boundary.dashpot.assign(n_nodes, Vec2::Zero());
  boundary.incident.assign(n_nodes, Vec2::Zero());
  boundary.static_force.assign(n_nodes, Vec2::Zero());
  boundary.dashpots_in_base_frame = spec.base == SeismicBase::rigid;
  const std::vector<std::uint8_t> on_base = set_up_base(model, spec, reactions, boundary);
  if (spec.lateral == LateralBoundary::boundaries) return boundary;

  const bool rigid = spec.base == SeismicBase::rigid;
  const Side left(model.mesh, "left", on_base, rigid);
  const Side right(model.mesh, "right", on_base, rigid);
  // Viscous sides, and the nodes of tied sides without a partner, get Lysmer dashpots.
  std::vector<std::uint8_t> paired(n_nodes, 0);
  if (spec.lateral != LateralBoundary::viscous) {
    paired = tie_sides(model, spec, left, right, reactions, boundary);
  }
  for (const Side* side : {&left, &right}) {
    for (const auto& [y, node] : side->nodes) {
      if (!paired[static_cast<std::size_t>(node)]) {
        make_viscous(model, node, side->length.at(node), reactions, boundary);
      }
    }
  }
  return boundary;
}

std::string describe(const SeismicBoundary& boundary, const MotionSpec& spec) {
  std::string text;
  if (spec.base == SeismicBase::rigid) {
    text = "rigid base (the constraints of fem.failure.boundaries move with it)";
  } else {
    text = fmt::format("compliant base: ρ_r V_s,r = {:.4g} Pa·s/m{}, {} input",
                       spec.rock_density * spec.rock_shear_wave_speed,
                       spec.vertical ? fmt::format(", ρ_r V_p,r = {:.4g} Pa·s/m",
                                                   spec.rock_density * spec.rock_p_wave_speed)
                                     : std::string(", vertical roller"),
                       to_string(spec.input));
  }
  const Index viscous = boundary.viscous_side_nodes;
  switch (spec.lateral) {
    case LateralBoundary::boundaries:
      text += "; sides as fem.failure.boundaries";
      break;
    case LateralBoundary::tied:
    case LateralBoundary::tied_horizontal:
      text += fmt::format("; tied sides ({}): {} pairs, {} unpaired nodes viscous",
                          boundary.tie_vertical ? "both components" : "horizontal",
                          boundary.tied.size(), viscous);
      break;
    case LateralBoundary::viscous:
      text += fmt::format("; viscous sides: {} nodes", viscous);
      break;
  }
  return text;
}

}  // namespace slide::fem
