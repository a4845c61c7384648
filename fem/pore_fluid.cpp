#include "fem/pore_fluid.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <tuple>

#include "common/base/error.hpp"

namespace slide::fem {

namespace {

/// γ_w = ρ_w g_n: a hydraulic conductivity is measured under the earth's gravity, so k/γ_w
/// (the permeability over the fluid's viscosity) is a property of the soil whatever the
/// model's gravity (a gravity-free verification model keeps its flow).
constexpr double standard_gravity = 9.81;

/// t = L (d·K n)/(d·d), the half-transmissibility of a face from an element's centre
/// (d = midpoint − centre, n the outward normal, L the face's length, K = diag(k)/γ_w); on
/// a face so skewed that d·K n ≤ 0, the orthogonal part L (n·K n)/|d|.
double half_transmissibility(const Vec2& d, const Vec2& normal, double length,
                             const Vec2& mobility) {
  const Vec2 flow = mobility.cwiseProduct(normal);
  const double t = length * d.dot(flow) / d.squaredNorm();
  return t > 0.0 ? t : length * normal.dot(flow) / d.norm();
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
    if (fluid.node_storage[n] > 0.0) {
      fluid.hydrostatic[n] = std::max(fluid.hydrostatic_at(mesh.nodes[n]), fluid.tension_limit);
    }
    fluid.prescribed[n] = fluid.node_storage[n] > 0.0 && fluid.depth(mesh.nodes[n]) > 0.0 ? 0 : 1;
  }
  for (const std::string& name : drained) {
    const NodeSet* set = mesh.find_node_set(name);
    if (set == nullptr) {
      throw Error("fem.water.drained: \"{}\" is not a node set of the mesh", name);
    }
    for (const Index node : set->nodes) fluid.prescribed[static_cast<std::size_t>(node)] = 1;
  }
}

/// One side of an element: its end nodes (sorted, the key that finds its neighbour) and
/// the element.
struct Side {
  Index low = 0, high = 0;
  Index element = 0;
  auto key() const { return std::tie(low, high, element); }
};

/// The sides of the elements (of the saturated ones only when `saturated_only`), sorted so
/// that a side two of them share is two neighbouring entries.
std::vector<Side> sorted_sides(const FemModel& model, bool saturated_only) {
  const int corners = model.nodes_per_element;
  std::vector<Side> sides;
  for (Index e = 0; e < model.mesh.element_count(); ++e) {
    if (saturated_only && !model.fluid.saturated[static_cast<std::size_t>(e)]) continue;
    const auto nodes = model.mesh.element(e);
    for (int k = 0; k < corners; ++k) {
      const Index a = nodes[static_cast<std::size_t>(k)];
      const Index b = nodes[static_cast<std::size_t>((k + 1) % corners)];
      sides.push_back(Side{std::min(a, b), std::max(a, b), e});
    }
  }
  std::ranges::sort(sides, [](const Side& x, const Side& y) { return x.key() < y.key(); });
  return sides;
}

/// A boundary side under a reservoir: its nodes (sorted) and the water's pressure at them.
struct WettedSide {
  Index low = 0, high = 0;
  /// ρ_w g times the depth below the reservoir's surface at the two nodes (negative above
  /// it: a side the surface crosses is wet on one part only), Pa.
  double p_low = 0.0, p_high = 0.0;
  Vec2 inward = Vec2::Zero();  ///< the unit normal into the body
  /// The pressure at the side's midpoint (> 0: it is below the surface), Pa.
  double middle() const { return 0.5 * (p_low + p_high); }
  auto key() const { return std::pair{low, high}; }
};

/// The unit normal of the side a–b that points away from `inside` (its element's centre).
Vec2 outward_normal(const Vec2& a, const Vec2& b, const Vec2& inside) {
  Vec2 normal(b.y() - a.y(), a.x() - b.x());
  normal.normalize();
  return normal.dot(0.5 * (a + b) - inside) < 0.0 ? Vec2(-normal) : normal;
}

/// The model's boundary sides a reservoir wets: facing up (their outward normal against
/// gravity) with their midpoint below the reservoir's surface. Sorted by their nodes.
std::vector<WettedSide> wetted_sides(const FemModel& model, const std::vector<Vec2>& centre) {
  const PoreFluid& fluid = model.fluid;
  std::vector<WettedSide> wetted;
  if (!fluid.reservoir_point) return wetted;
  const Mesh& mesh = model.mesh;
  const double g = fluid.gravity.norm();
  const Vec2 down = g > 0.0 ? Vec2(fluid.gravity / g) : Vec2(0.0, -1.0);
  const auto depth = [&](const Vec2& x) { return down.dot(x - *fluid.reservoir_point); };
  const std::vector<Side> sides = sorted_sides(model, false);
  for (std::size_t i = 0; i < sides.size(); ++i) {
    const Side& s = sides[i];
    if (i + 1 < sides.size() && sides[i + 1].low == s.low && sides[i + 1].high == s.high) {
      ++i;  // an inner side
      continue;
    }
    const Vec2& a = mesh.nodes[static_cast<std::size_t>(s.low)];
    const Vec2& b = mesh.nodes[static_cast<std::size_t>(s.high)];
    const Vec2 normal = outward_normal(a, b, centre[static_cast<std::size_t>(s.element)]);
    const Vec2 middle = 0.5 * (a + b);
    if (!(normal.dot(-down) > 1e-9) || !(depth(middle) > 0.0)) continue;
    if (middle.x() < fluid.reservoir_extent.x() || middle.x() > fluid.reservoir_extent.y()) {
      continue;
    }
    wetted.push_back(WettedSide{s.low, s.high, fluid.density * g * depth(a),
                                fluid.density * g * depth(b), -normal});
  }
  return wetted;
}

/// ∫ N_a p ds and ∫ N_b p ds over a side of length L whose water pressure is linear from
/// p_a to p_b where it is positive and 0 above the surface: L (2 p_a + p_b)/6 and
/// L (p_a + 2 p_b)/6 when the side is all wet; when the surface crosses it at t₀ (from a),
/// with only b wet, L p_b (1 − t₀)²/6 and L p_b (1 − t₀)(2 + t₀)/6.
std::array<double, 2> wet_side_shares(double p_a, double p_b, double length) {
  if (p_a >= 0.0 && p_b >= 0.0) {
    return {length * (2.0 * p_a + p_b) / 6.0, length * (p_a + 2.0 * p_b) / 6.0};
  }
  if (p_a <= 0.0 && p_b <= 0.0) return {0.0, 0.0};
  if (p_a < 0.0) {
    const double t0 = p_a / (p_a - p_b);
    return {length * p_b * (1.0 - t0) * (1.0 - t0) / 6.0,
            length * p_b * (1.0 - t0) * (2.0 + t0) / 6.0};
  }
  const auto [to_b, to_a] = wet_side_shares(p_b, p_a, length);
  return {to_a, to_b};
}

/// The reservoir's water load on the solid: on each wetted side the consistent nodal
/// forces of its pressure along the inward normal (wet_side_shares).
void add_reservoir_load(FemModel& model, const std::vector<WettedSide>& wetted) {
  for (const WettedSide& w : wetted) {
    const Vec2& a = model.mesh.nodes[static_cast<std::size_t>(w.low)];
    const Vec2& b = model.mesh.nodes[static_cast<std::size_t>(w.high)];
    const auto [share_a, share_b] = wet_side_shares(w.p_low, w.p_high, (b - a).norm());
    model.lumped.external_force[static_cast<std::size_t>(w.low)] += share_a * w.inward;
    model.lumped.external_force[static_cast<std::size_t>(w.high)] += share_b * w.inward;
  }
}

/// The faces water crosses: between saturated neighbours; drained faces of saturated
/// elements, at the reservoir's pressure where it wets them, else at the hydrostatic
/// pressure of the table where both nodes are held.
void make_faces(FemModel& model, const std::vector<Vec2>& centre,
                const std::vector<WettedSide>& wetted) {
  PoreFluid& fluid = model.fluid;
  const Mesh& mesh = model.mesh;
  const std::vector<Side> sides = sorted_sides(model, true);
  const auto mobility = [&](Index e) -> Vec2 {
    const Material& m = model.material_of(e);
    return Vec2(m.conductivity_x, m.conductivity_y) / (fluid.density * standard_gravity);
  };
  const auto geometry = [&](const Side& s) {
    const Vec2& a = mesh.nodes[static_cast<std::size_t>(s.low)];
    const Vec2& b = mesh.nodes[static_cast<std::size_t>(s.high)];
    return std::tuple{Vec2(0.5 * (a + b)),
                      outward_normal(a, b, centre[static_cast<std::size_t>(s.element)]),
                      (b - a).norm()};
  };
  fluid.faces.clear();
  for (std::size_t i = 0; i < sides.size(); ++i) {
    const Side& s = sides[i];
    const auto [middle, normal, length] = geometry(s);
    const auto from = static_cast<std::size_t>(s.element);
    const double t_from =
        half_transmissibility(middle - centre[from], normal, length, mobility(s.element));
    if (i + 1 < sides.size() && sides[i + 1].low == s.low && sides[i + 1].high == s.high) {
      const Side& other = sides[++i];
      const auto to = static_cast<std::size_t>(other.element);
      const double t_to =
          half_transmissibility(middle - centre[to], -normal, length, mobility(other.element));
      if (t_from > 0.0 && t_to > 0.0) {
        fluid.faces.push_back(FluidFace{s.element, other.element, t_from * t_to / (t_from + t_to),
                                        centre[to] - centre[from], 0.0});
      }
      continue;
    }
    auto wet = std::ranges::lower_bound(wetted, std::pair{s.low, s.high}, {}, &WettedSide::key);
    if (wet != wetted.end() && wet->key() != std::pair{s.low, s.high}) wet = wetted.end();
    const bool drained = fluid.prescribed[static_cast<std::size_t>(s.low)] &&
                         fluid.prescribed[static_cast<std::size_t>(s.high)];
    if (!(t_from > 0.0) || (wet == wetted.end() && !drained)) continue;
    const double pressure = wet != wetted.end()
                                ? wet->middle()
                                : std::max(fluid.hydrostatic_at(middle), fluid.tension_limit);
    fluid.faces.push_back(
        FluidFace{s.element, -1, t_from, middle - centre[from], pressure, {s.low, s.high}});
  }
}

template <int NPE>
void add_forces(const FemModel& model, const ElementGeometry& geometry,
                std::span<const double> element_pressure, std::span<Vec2> element_force) {
  const PoreFluid& fluid = model.fluid;
  const int ngp = model.gauss_per_element();
  for (Index e = 0; e < model.element_count(); ++e) {
    const auto ei = static_cast<std::size_t>(e);
    if (!fluid.saturated[ei]) continue;
    for (int g = 0; g < ngp; ++g) {
      const auto gp = static_cast<std::size_t>(e * ngp + g);
      const double wp = geometry.weight[gp] * element_pressure[ei];
      const ShapeGradients& b = geometry.gradients[gp];
      for (int k = 0; k < NPE; ++k) {
        element_force[static_cast<std::size_t>(e * NPE + k)] += wp * Vec2(b(k, 0), b(k, 1));
      }
    }
  }
}

/// S_e ṗ_e of every element: −∫∇·v dA (at the element's own Gauss points) minus the flow out
/// across its faces.
template <int NPE>
void pressure_rates(const FemModel& model, const ElementGeometry& geometry, const FemState& state,
                    PressureScratch& scratch) {
  const PoreFluid& fluid = model.fluid;
  const int ngp = model.gauss_per_element();
  const Index* connectivity = model.mesh.connectivity.data();
  for (Index e = 0; e < model.element_count(); ++e) {
    const auto ei = static_cast<std::size_t>(e);
    scratch.rate[ei] = 0.0;
    if (!fluid.saturated[ei]) continue;
    const Index* nodes = connectivity + e * NPE;
    double volume_rate = 0.0;
    Vec2 acceleration = Vec2::Zero();
    for (int k = 0; k < NPE; ++k)
      acceleration += state.acceleration[static_cast<std::size_t>(nodes[k])];
    scratch.acceleration[ei] = acceleration / NPE;
    for (int g = 0; g < ngp; ++g) {
      const auto gp = static_cast<std::size_t>(e * ngp + g);
      const ShapeGradients& b = geometry.gradients[gp];
      double divergence = 0.0;
      for (int k = 0; k < NPE; ++k) {
        const Vec2& v = state.velocity[static_cast<std::size_t>(nodes[k])];
        divergence += b(k, 0) * v.x() + b(k, 1) * v.y();
      }
      volume_rate += geometry.weight[gp] * divergence;
    }
    scratch.rate[ei] = -volume_rate;
  }
  const std::vector<double>& p = state.element_pore_pressure;
  for (const FluidFace& face : fluid.faces) {
    const auto a = static_cast<std::size_t>(face.from);
    const bool inner = face.to >= 0;
    const auto b = static_cast<std::size_t>(inner ? face.to : face.from);
    const Vec2 drive_acceleration =
        inner ? 0.5 * (scratch.acceleration[a] + scratch.acceleration[b]) : scratch.acceleration[a];
    const double p_to = inner ? p[b] : face.pressure;
    const double flow =
        face.transmissibility *
        (p[a] - p_to + fluid.density * (fluid.gravity - drive_acceleration).dot(face.offset));
    scratch.rate[a] -= flow;
    if (inner) scratch.rate[b] += flow;
  }
}

/// Δp_e = p_e − the element's mean of the nodal p_static (the hydrostatic field is linear,
/// so the mean is its value at the centre).
double element_excess(const FemModel& model, const FemState& state, Index e) {
  const auto nodes = model.mesh.element(e);
  double base = 0.0;
  for (const Index n : nodes) base += state.static_pore_pressure[static_cast<std::size_t>(n)];
  return state.element_pore_pressure[static_cast<std::size_t>(e)] -
         base / static_cast<double>(nodes.size());
}

/// f(gp, r_u) for every Gauss point of a saturated element whose σ′v0 is at least
/// min_ratio_stress, r_u = Δp_e/σ′v0.
template <class F>
void for_each_ratio(const FemModel& model, const FemState& state, F&& f) {
  const int ngp = model.gauss_per_element();
  for (Index e = 0; e < model.element_count(); ++e) {
    if (!model.fluid.saturated[static_cast<std::size_t>(e)]) continue;
    const double excess = element_excess(model, state, e);
    for (int g = 0; g < ngp; ++g) {
      const auto gp = static_cast<std::size_t>(e * ngp + g);
      const double stress = state.initial_vertical_effective_stress[gp];
      if (stress >= min_ratio_stress) f(gp, excess / stress);
    }
  }
}

/// Raises each Gauss point's r_u,max to its r_u of now (a checkpoint written before the
/// field existed starts it at 0).
void track_max_ratio(const FemModel& model, FemState& state) {
  auto& max_ratio = state.max_pore_pressure_ratio;
  max_ratio.resize(static_cast<std::size_t>(model.gauss_count()), 0.0);
  for_each_ratio(model, state, [&](std::size_t gp, double ratio) {
    max_ratio[gp] = std::max(max_ratio[gp], ratio);
  });
}

}  // namespace

void make_pore_fluid(FemModel& model, std::span<const std::string> drained) {
  PoreFluid& fluid = model.fluid;
  const Mesh& mesh = model.mesh;
  const ElementShape shape = mesh.shape();
  const auto n_elements = static_cast<std::size_t>(mesh.element_count());
  const auto n_nodes = static_cast<std::size_t>(mesh.node_count());
  fluid.saturated.assign(n_elements, 0);
  fluid.storage.assign(n_elements, 0.0);
  fluid.element_hydrostatic.assign(n_elements, 0.0);
  fluid.node_storage.assign(n_nodes, 0.0);
  std::vector<Vec2> centre(n_elements);
  for (std::size_t e = 0; e < n_elements; ++e) {
    const auto ei = static_cast<Index>(e);
    const Material& material = model.material_of(ei);
    const ElementNodes x = mesh.element_nodes(ei, mesh.nodes);
    centre[e] = map_to_physical(shape, x, reference_centre(shape));
    if (!material.saturable() || !(fluid.depth(centre[e]) > 0.0)) continue;
    fluid.saturated[e] = 1;
    fluid.storage[e] = material.porosity / fluid.bulk_modulus * std::abs(element_area(shape, x));
    for (const Index n : mesh.element(ei)) {
      fluid.node_storage[static_cast<std::size_t>(n)] += fluid.storage[e];
    }
  }
  if (std::ranges::none_of(fluid.saturated, [](std::uint8_t s) { return s != 0; })) {
    throw Error(
        "fem.water: no element is saturated (no material has a porosity, or every porous "
        "element lies above the water level {} m)",
        fluid.level_point.y());
  }
  hold_nodes(model, drained);
  // p_h at the centre as the mean of the nodes' (the field is linear, and so the excess
  // p − mean of the nodal p_static of the rest state is exactly 0).
  const std::vector<double> mean = element_mean_of_nodes(model, fluid.hydrostatic);
  for (std::size_t e = 0; e < n_elements; ++e) {
    if (fluid.saturated[e]) fluid.element_hydrostatic[e] = mean[e];
  }
  const std::vector<WettedSide> wetted = wetted_sides(model, centre);
  make_faces(model, centre, wetted);
  add_reservoir_load(model, wetted);
}

void add_pore_pressure_forces(const FemModel& model, const ElementGeometry& geometry,
                              std::span<const double> element_pressure,
                              std::span<Vec2> element_force) {
  if (!model.fluid.active()) return;
  if (model.nodes_per_element == 4) {
    add_forces<4>(model, geometry, element_pressure, element_force);
  } else {
    add_forces<3>(model, geometry, element_pressure, element_force);
  }
}

PorePressureStep advance_pore_pressure(const FemModel& model, const ElementGeometry& geometry,
                                       double dt, std::span<const std::pair<Index, Index>> tied,
                                       FemState& state, PressureScratch& scratch) {
  PorePressureStep result;
  const PoreFluid& fluid = model.fluid;
  if (!fluid.active()) return result;
  scratch.rate.resize(fluid.storage.size());
  scratch.acceleration.resize(fluid.storage.size());
  if (model.nodes_per_element == 4) {
    pressure_rates<4>(model, geometry, state, scratch);
  } else {
    pressure_rates<3>(model, geometry, state, scratch);
  }
  for (std::size_t e = 0; e < fluid.storage.size(); ++e) {
    if (!fluid.saturated[e]) continue;
    const double p = state.element_pore_pressure[e] + dt * scratch.rate[e] / fluid.storage[e];
    if (p < fluid.tension_limit) ++result.clamped;
    state.element_pore_pressure[e] = std::max(p, fluid.tension_limit);
  }
  for (const auto& [i, j] : tied) {
    const auto a = static_cast<std::size_t>(i), c = static_cast<std::size_t>(j);
    if (!fluid.saturated[a] || !fluid.saturated[c]) continue;
    double& pa = state.element_pore_pressure[a];
    double& pc = state.element_pore_pressure[c];
    pa = pc =
        (fluid.storage[a] * pa + fluid.storage[c] * pc) / (fluid.storage[a] + fluid.storage[c]);
  }
  update_nodal_pore_pressure(model, state);
  track_max_ratio(model, state);
  return result;
}

void update_nodal_pore_pressure(const FemModel& model, FemState& state) {
  const PoreFluid& fluid = model.fluid;
  if (!fluid.active()) return;
  std::vector<double>& p = state.pore_pressure;
  std::ranges::fill(p, 0.0);
  for (Index e = 0; e < model.element_count(); ++e) {
    const auto ei = static_cast<std::size_t>(e);
    if (!fluid.saturated[ei]) continue;
    const double share =
        fluid.storage[ei] * (state.element_pore_pressure[ei] - fluid.element_hydrostatic[ei]);
    for (const Index n : model.mesh.element(e)) p[static_cast<std::size_t>(n)] += share;
  }
  for (std::size_t n = 0; n < p.size(); ++n) {
    p[n] = fluid.hydrostatic[n] + (fluid.prescribed[n] ? 0.0 : p[n] / fluid.node_storage[n]);
  }
}

std::vector<double> element_mean_of_nodes(const FemModel& model, std::span<const double> nodal) {
  std::vector<double> mean(static_cast<std::size_t>(model.element_count()), 0.0);
  for (Index e = 0; e < model.element_count(); ++e) {
    const auto nodes = model.mesh.element(e);
    double sum = 0.0;
    for (const Index n : nodes) sum += nodal[static_cast<std::size_t>(n)];
    mean[static_cast<std::size_t>(e)] = sum / static_cast<double>(nodes.size());
  }
  return mean;
}

std::vector<double> element_pressure_from_nodes(const FemModel& model,
                                                std::span<const double> nodal) {
  std::vector<double> p = element_mean_of_nodes(model, nodal);
  for (std::size_t e = 0; e < p.size(); ++e) {
    if (!model.fluid.active() || !model.fluid.saturated[e]) p[e] = 0.0;
  }
  return p;
}

double pore_fluid_time_step(const FemModel& model) {
  const PoreFluid& fluid = model.fluid;
  double smallest = std::numeric_limits<double>::infinity();
  if (!fluid.active()) return smallest;
  std::vector<double> conductance(fluid.storage.size(), 0.0);
  for (const FluidFace& face : fluid.faces) {
    conductance[static_cast<std::size_t>(face.from)] += face.transmissibility;
    if (face.to >= 0) conductance[static_cast<std::size_t>(face.to)] += face.transmissibility;
  }
  for (std::size_t e = 0; e < conductance.size(); ++e) {
    if (conductance[e] > 0.0) smallest = std::min(smallest, fluid.storage[e] / conductance[e]);
  }
  return smallest;
}

double drained_outflow(const FemModel& model, const FemState& state, const FluidFace& face) {
  const PoreFluid& fluid = model.fluid;
  Vec2 acceleration = Vec2::Zero();
  const auto nodes = model.mesh.element(face.from);
  for (const Index n : nodes) acceleration += state.acceleration[static_cast<std::size_t>(n)];
  acceleration /= static_cast<double>(nodes.size());
  return face.transmissibility *
         (state.element_pore_pressure[static_cast<std::size_t>(face.from)] - face.pressure +
          fluid.density * (fluid.gravity - acceleration).dot(face.offset));
}

void gauss_point_pressure(const FemModel& model, std::span<const double> element_pressure,
                          std::vector<double>& out) {
  const int ngp = model.gauss_per_element();
  out.assign(static_cast<std::size_t>(model.gauss_count()), 0.0);
  if (!model.fluid.active()) return;
  for (Index e = 0; e < model.element_count(); ++e) {
    if (!model.fluid.saturated[static_cast<std::size_t>(e)]) continue;
    for (int g = 0; g < ngp; ++g) {
      out[static_cast<std::size_t>(e * ngp + g)] = element_pressure[static_cast<std::size_t>(e)];
    }
  }
}

ElementPoreWater element_pore_water(const FemModel& model, const FemState& state, Index e) {
  ElementPoreWater water;
  if (!model.fluid.active() || !model.fluid.saturated[static_cast<std::size_t>(e)]) return water;
  const int ngp = model.gauss_per_element();
  const double excess = element_excess(model, state, e);
  water.pressure = state.element_pore_pressure[static_cast<std::size_t>(e)];
  for (int g = 0; g < ngp; ++g) {
    const double stress =
        state.initial_vertical_effective_stress[static_cast<std::size_t>(e * ngp + g)];
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
  out.assign(static_cast<std::size_t>(model.gauss_count()), 0.0);
  if (!model.fluid.active() || state.element_pore_pressure.empty()) return;
  for_each_ratio(model, state, [&](std::size_t gp, double ratio) { out[gp] = ratio; });
}

}  // namespace slide::fem
