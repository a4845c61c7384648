#include "fem/pore_fluid.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "common/base/error.hpp"

namespace slide::fem {

namespace {

/// γ_w = ρ_w g_n: a hydraulic conductivity is measured under the earth's gravity, so k/γ_w
/// (the permeability over the fluid's viscosity) is a property of the soil whatever the
/// model's gravity (a gravity-free verification model keeps its flow).
constexpr double standard_gravity = 9.81;

/// The rule the Darcy term is integrated with: the full rule of the element's shape.
std::vector<QuadraturePoint> flux_rule(ElementShape shape) {
  if (shape == ElementShape::quad4) return tensor_gauss_legendre(2, 2);
  return {QuadraturePoint{reference_centre(shape), reference_measure(shape)}};
}

template <int NPE>
double element_pressure(const Index* nodes, std::span<const double> p, const ShapeValues& n) {
  double value = 0.0;
  for (int k = 0; k < NPE; ++k)
    value += n[static_cast<std::size_t>(k)] * p[static_cast<std::size_t>(nodes[k])];
  return value;
}

template <int NPE>
void add_forces(const FemModel& model, const ElementGeometry& geometry,
                std::span<const double> pore_pressure, std::span<Vec2> element_force) {
  const PoreFluid& fluid = model.fluid;
  const int ngp = model.gauss_per_element();
  const Index* connectivity = model.mesh.connectivity.data();
  for (Index e = 0; e < model.element_count(); ++e) {
    if (!fluid.saturated[static_cast<std::size_t>(e)]) continue;
    const Index* nodes = connectivity + e * NPE;
    for (int g = 0; g < ngp; ++g) {
      const auto gp = static_cast<std::size_t>(e * ngp + g);
      const double wp = geometry.weight[gp] *
                        element_pressure<NPE>(nodes, pore_pressure,
                                              fluid.gauss_shape[static_cast<std::size_t>(g)]);
      const ShapeGradients& b = geometry.gradients[gp];
      for (int k = 0; k < NPE; ++k) {
        element_force[static_cast<std::size_t>(e * NPE + k)] += wp * Vec2(b(k, 0), b(k, 1));
      }
    }
  }
}

template <int NPE>
void pressure_rates(const FemModel& model, const ElementGeometry& geometry, const FemState& state,
                    std::vector<double>& rate) {
  const PoreFluid& fluid = model.fluid;
  const int ngp = model.gauss_per_element();
  const int nfp = fluid.flux_points;
  const Index* connectivity = model.mesh.connectivity.data();
  std::fill(rate.begin(), rate.end(), 0.0);
  for (Index e = 0; e < model.element_count(); ++e) {
    const auto ei = static_cast<std::size_t>(e);
    if (!fluid.saturated[ei]) continue;
    const Index* nodes = connectivity + e * NPE;
    std::array<double, NPE> r{};
    // −Qᵀ v: −Σ_gp w N_k(gp) ∇·v(gp), at the element's own Gauss points.
    for (int g = 0; g < ngp; ++g) {
      const auto gp = static_cast<std::size_t>(e * ngp + g);
      const ShapeGradients& b = geometry.gradients[gp];
      double divergence = 0.0;
      for (int k = 0; k < NPE; ++k) {
        const Vec2& v = state.velocity[static_cast<std::size_t>(nodes[k])];
        divergence += b(k, 0) * v.x() + b(k, 1) * v.y();
      }
      const ShapeValues& n = fluid.gauss_shape[static_cast<std::size_t>(g)];
      const double w = geometry.weight[gp] * divergence;
      for (int k = 0; k < NPE; ++k)
        r[static_cast<std::size_t>(k)] -= w * n[static_cast<std::size_t>(k)];
    }
    // Darcy: Σ_fp w ∇N_k · q, q = −(k/γ_w)(∇p − ρ_w (g − a)).
    const Vec2& mobility = fluid.mobility[ei];
    for (int f = 0; f < nfp; ++f) {
      const auto fp = static_cast<std::size_t>(e * nfp + f);
      const ShapeGradients& b = fluid.flux_gradients[fp];
      const ShapeValues& n = fluid.flux_shape[static_cast<std::size_t>(f)];
      Vec2 gradient = Vec2::Zero(), acceleration = Vec2::Zero();
      for (int k = 0; k < NPE; ++k) {
        const auto node = static_cast<std::size_t>(nodes[k]);
        gradient += state.pore_pressure[node] * Vec2(b(k, 0), b(k, 1));
        acceleration += n[static_cast<std::size_t>(k)] * state.acceleration[node];
      }
      const Vec2 drive = gradient - fluid.density * (fluid.gravity - acceleration);
      const Vec2 flux = -fluid.flux_weight[fp] * mobility.cwiseProduct(drive);
      for (int k = 0; k < NPE; ++k)
        r[static_cast<std::size_t>(k)] += b(k, 0) * flux.x() + b(k, 1) * flux.y();
    }
    for (int k = 0; k < NPE; ++k)
      rate[static_cast<std::size_t>(nodes[k])] += r[static_cast<std::size_t>(k)];
  }
}

/// Per node the hydrostatic p (suction above the table, down to the tension limit) and
/// whether p is held at it: off the saturated elements, on or above the table, drained.
void hold_nodes(FemModel& model, std::span<const std::string> drained) {
  PoreFluid& fluid = model.fluid;
  const Mesh& mesh = model.mesh;
  const auto n_nodes = static_cast<std::size_t>(mesh.node_count());
  fluid.hydrostatic.assign(n_nodes, 0.0);
  fluid.prescribed.assign(n_nodes, 0);
  for (std::size_t n = 0; n < n_nodes; ++n) {
    if (fluid.storage[n] > 0.0) {
      fluid.hydrostatic[n] = std::max(fluid.hydrostatic_at(mesh.nodes[n]), fluid.tension_limit);
    }
    fluid.prescribed[n] = fluid.storage[n] > 0.0 && fluid.depth(mesh.nodes[n]) > 0.0 ? 0 : 1;
  }
  for (const std::string& name : drained) {
    const NodeSet* set = mesh.find_node_set(name);
    if (set == nullptr) {
      throw Error("fem.water.drained: \"{}\" is not a node set of the mesh", name);
    }
    for (const Index node : set->nodes) fluid.prescribed[static_cast<std::size_t>(node)] = 1;
  }
}

}  // namespace

void make_pore_fluid(FemModel& model, std::span<const std::string> drained) {
  PoreFluid& fluid = model.fluid;
  const Mesh& mesh = model.mesh;
  const ElementShape shape = mesh.shape();
  const auto n_elements = static_cast<std::size_t>(mesh.element_count());
  const auto n_nodes = static_cast<std::size_t>(mesh.node_count());
  const double unit_weight = fluid.density * standard_gravity;
  const std::vector<QuadraturePoint> rule = flux_rule(shape);
  fluid.flux_points = static_cast<int>(rule.size());
  fluid.flux_shape.clear();
  for (const QuadraturePoint& q : rule) fluid.flux_shape.push_back(shape_functions(shape, q.xi));
  fluid.gauss_shape.clear();
  for (const Vec2& xi : model.rule.local) fluid.gauss_shape.push_back(shape_functions(shape, xi));

  fluid.saturated.assign(n_elements, 0);
  fluid.mobility.assign(n_elements, Vec2::Zero());
  fluid.flux_gradients.resize(n_elements * rule.size());
  fluid.flux_weight.resize(n_elements * rule.size());
  fluid.storage.assign(n_nodes, 0.0);
  const Vec2 centre = reference_centre(shape);
  for (std::size_t e = 0; e < n_elements; ++e) {
    const auto ei = static_cast<Index>(e);
    const Material& material = model.material_of(ei);
    const ElementNodes x = mesh.element_nodes(ei, mesh.nodes);
    for (std::size_t f = 0; f < rule.size(); ++f) {
      double det = 0.0;
      fluid.flux_gradients[e * rule.size() + f] = physical_gradients(shape, x, rule[f].xi, &det);
      fluid.flux_weight[e * rule.size() + f] = rule[f].weight * det;
    }
    if (!material.saturable() || !(fluid.depth(map_to_physical(shape, x, centre)) > 0.0)) {
      continue;
    }
    fluid.saturated[e] = 1;
    fluid.mobility[e] = Vec2(material.conductivity_x, material.conductivity_y) / unit_weight;
    const ShapeValues storage =
        lumped_element_mass(shape, x, material.porosity / fluid.bulk_modulus);
    const auto nodes = mesh.element(ei);
    for (std::size_t k = 0; k < nodes.size(); ++k) {
      fluid.storage[static_cast<std::size_t>(nodes[k])] += storage[k];
    }
  }
  if (std::ranges::none_of(fluid.saturated, [](std::uint8_t s) { return s != 0; })) {
    throw Error(
        "fem.water: no element is saturated (no material has a porosity, or every porous "
        "element lies above the water level {} m)",
        fluid.level_point.y());
  }
  hold_nodes(model, drained);
}

void add_pore_pressure_forces(const FemModel& model, const ElementGeometry& geometry,
                              std::span<const double> pore_pressure,
                              std::span<Vec2> element_force) {
  if (!model.fluid.active()) return;
  if (model.nodes_per_element == 4) {
    add_forces<4>(model, geometry, pore_pressure, element_force);
  } else {
    add_forces<3>(model, geometry, pore_pressure, element_force);
  }
}

PorePressureStep advance_pore_pressure(const FemModel& model, const ElementGeometry& geometry,
                                       double dt, FemState& state, std::vector<double>& rate) {
  PorePressureStep result;
  const PoreFluid& fluid = model.fluid;
  if (!fluid.active()) return result;
  rate.resize(fluid.storage.size());
  if (model.nodes_per_element == 4) {
    pressure_rates<4>(model, geometry, state, rate);
  } else {
    pressure_rates<3>(model, geometry, state, rate);
  }
  for (std::size_t n = 0; n < rate.size(); ++n) {
    if (fluid.prescribed[n]) {
      state.pore_pressure[n] = fluid.hydrostatic[n];
      continue;
    }
    const double p = state.pore_pressure[n] + dt * rate[n] / fluid.storage[n];
    if (p < fluid.tension_limit) ++result.clamped;
    state.pore_pressure[n] = std::max(p, fluid.tension_limit);
  }
  return result;
}

void tie_pore_pressure(const FemModel& model, std::span<const std::pair<Index, Index>> tied,
                       FemState& state) {
  const PoreFluid& fluid = model.fluid;
  if (!fluid.active()) return;
  for (const auto& [i, j] : tied) {
    const auto a = static_cast<std::size_t>(i), c = static_cast<std::size_t>(j);
    double& pa = state.pore_pressure[a];
    double& pc = state.pore_pressure[c];
    if (fluid.prescribed[a] || fluid.prescribed[c]) {
      if (!fluid.prescribed[c]) pc = pa;
      if (!fluid.prescribed[a]) pa = pc;
      continue;
    }
    pa = pc =
        (fluid.storage[a] * pa + fluid.storage[c] * pc) / (fluid.storage[a] + fluid.storage[c]);
  }
}

double pore_fluid_time_step(const FemModel& model) {
  const PoreFluid& fluid = model.fluid;
  double smallest = std::numeric_limits<double>::infinity();
  if (!fluid.active()) return smallest;
  const Mesh& mesh = model.mesh;
  const int n = model.nodes_per_element;
  const double area_factor = mesh.shape() == ElementShape::tri3 ? 2.0 : 1.0;
  for (Index e = 0; e < mesh.element_count(); ++e) {
    const auto ei = static_cast<std::size_t>(e);
    if (!fluid.saturated[ei]) continue;
    const double mobility = fluid.mobility[ei].maxCoeff();
    if (!(mobility > 0.0)) continue;
    const double diffusivity = mobility * fluid.bulk_modulus / model.material_of(e).porosity;
    const ElementNodes x = mesh.element_nodes(e, mesh.nodes);
    double longest = 0.0;
    for (int k = 0; k < n; ++k) longest = std::max(longest, (x.row((k + 1) % n) - x.row(k)).norm());
    const double h = area_factor * std::abs(element_area(mesh.shape(), x)) / longest;
    smallest = std::min(smallest, h * h / (4.0 * diffusivity));
  }
  return smallest;
}

void gauss_point_pressure(const FemModel& model, std::span<const double> pore_pressure,
                          std::vector<double>& out) {
  const int npe = model.nodes_per_element;
  const int ngp = model.gauss_per_element();
  out.assign(static_cast<std::size_t>(model.gauss_count()), 0.0);
  if (!model.fluid.active()) return;
  for (Index e = 0; e < model.element_count(); ++e) {
    if (!model.fluid.saturated[static_cast<std::size_t>(e)]) continue;
    const auto nodes = model.mesh.element(e);
    for (int g = 0; g < ngp; ++g) {
      double p = 0.0;
      for (int k = 0; k < npe; ++k) {
        p += model.fluid.gauss_shape[static_cast<std::size_t>(g)][static_cast<std::size_t>(k)] *
             pore_pressure[static_cast<std::size_t>(nodes[static_cast<std::size_t>(k)])];
      }
      out[static_cast<std::size_t>(e * ngp + g)] = p;
    }
  }
}

ElementPoreWater element_pore_water(const FemModel& model, const FemState& state, Index e) {
  ElementPoreWater water;
  if (!model.fluid.active() || !model.fluid.saturated[static_cast<std::size_t>(e)]) return water;
  const auto nodes = model.mesh.element(e);
  const int ngp = model.gauss_per_element();
  for (int g = 0; g < ngp; ++g) {
    const ShapeValues& n = model.fluid.gauss_shape[static_cast<std::size_t>(g)];
    double p = 0.0, excess = 0.0;
    for (std::size_t k = 0; k < nodes.size(); ++k) {
      const auto node = static_cast<std::size_t>(nodes[k]);
      p += n[k] * state.pore_pressure[node];
      excess += n[k] * (state.pore_pressure[node] - state.static_pore_pressure[node]);
    }
    const double stress =
        state.initial_vertical_effective_stress[static_cast<std::size_t>(e * ngp + g)];
    water.pressure += p / static_cast<double>(ngp);
    water.ratio += (stress >= min_ratio_stress ? excess / stress : 0.0) / static_cast<double>(ngp);
  }
  return water;
}

std::vector<double> element_pore_pressure_ratio(const FemModel& model,
                                                std::span<const double> gauss_ratio) {
  const auto n_gauss = static_cast<std::size_t>(model.gauss_per_element());
  std::vector<double> ratio(static_cast<std::size_t>(model.element_count()), 0.0);
  for (std::size_t gp = 0; gp < gauss_ratio.size(); ++gp) {
    ratio[gp / n_gauss] += gauss_ratio[gp] / static_cast<double>(n_gauss);
  }
  return ratio;
}

std::vector<double> excess_pore_pressure(const FemState& state) {
  std::vector<double> excess;
  if (state.static_pore_pressure.size() != state.pore_pressure.size()) return excess;
  excess.reserve(state.pore_pressure.size());
  for (std::size_t n = 0; n < state.pore_pressure.size(); ++n) {
    excess.push_back(state.pore_pressure[n] - state.static_pore_pressure[n]);
  }
  return excess;
}

void pore_pressure_ratio(const FemModel& model, const FemState& state, std::vector<double>& out) {
  const std::vector<double> excess = excess_pore_pressure(state);
  if (excess.empty()) {
    out.assign(static_cast<std::size_t>(model.gauss_count()), 0.0);
    return;
  }
  gauss_point_pressure(model, excess, out);
  for (std::size_t gp = 0; gp < out.size(); ++gp) {
    const double stress = model.fluid.active() ? state.initial_vertical_effective_stress[gp] : 0.0;
    out[gp] = stress >= min_ratio_stress ? out[gp] / stress : 0.0;
  }
}

}  // namespace slide::fem
