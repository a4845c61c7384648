#include "transfer/pore_water.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include <fmt/format.h>

#include "common/base/error.hpp"
#include "common/base/numeric.hpp"
#include "common/geometry/element.hpp"
#include "common/physics/liquefaction.hpp"

namespace slide::transfer {

namespace {

std::string describe_rule(const LiquefactionParameters& rule) {
  std::string text;
  if (!std::isnan(rule.pore_pressure_ratio)) {
    text = fmt::format("r_u,max >= {:g}", rule.pore_pressure_ratio);
  }
  if (!std::isnan(rule.shear_strain)) {
    text += fmt::format("{}gamma >= {:g}", text.empty() ? "" : " or ", rule.shear_strain);
  }
  return text;
}

/// p_static at each particle, by its element's shape functions as p itself.
void interpolate_static_pressure(const FemCheckpoint& fem, std::span<const Vec2> xi,
                                 Particles& particles) {
  const ElementShape shape = fem.mesh.shape();
  for (std::size_t p = 0; p < particles.count(); ++p) {
    const ShapeValues n = shape_functions(shape, xi[p]);
    const auto nodes = fem.mesh.element(particles.element[p]);
    double p_static = 0.0;
    for (std::size_t k = 0; k < nodes.size(); ++k) {
      p_static += n[k] * fem.static_pore_pressure[static_cast<std::size_t>(nodes[k])];
    }
    particles.excess_pore_pressure[p] = particles.pore_pressure[p] - p_static;
  }
}

/// No more excess than the overburden it can lift: Δp ≤ σ′v0 (r_u ≤ 1). Beyond it the FE
/// state is a blow-out (p′ at its floor, the element held by its neighbours); in MPM the
/// surplus would push a particle's neighbours apart with nothing to hold it. True when
/// particle p's Δp was capped.
bool cap_excess(Particles& particles, std::size_t p) {
  const double limit = std::max(particles.initial_vertical_effective_stress[p], 0.0);
  if (!(particles.excess_pore_pressure[p] > limit)) return false;
  particles.pore_pressure[p] -= particles.excess_pore_pressure[p] - limit;
  particles.excess_pore_pressure[p] = limit;
  return true;
}

/// ∫ p dA of the FE state: each saturated element's p_e on its deformed volume.
double fe_pore_force(const FemCheckpoint& fem) {
  CompensatedSum sum;
  for (std::size_t e = 0; e < fem.element_pore_pressure.size(); ++e) {
    sum.add(fem.element_pore_pressure[e] * fem.volume[e]);
  }
  return sum.value();
}

/// A report row per material with a liquefaction rule; each material's row, −1 for none.
std::vector<std::ptrdiff_t> report_rows(const MaterialTable& materials,
                                        const std::vector<bool>& assumed, PoreWaterReport& report) {
  std::vector<std::ptrdiff_t> row_of(materials.size(), -1);
  for (std::size_t id = 0; id < materials.size(); ++id) {
    const Material& m = materials[id];
    if (!m.liquefaction.enabled) continue;
    row_of[id] = static_cast<std::ptrdiff_t>(report.materials.size());
    report.materials.push_back({.name = m.name,
                                .rule = assumed[id] ? std::string("assumed (--assume-liquefied)")
                                                    : describe_rule(m.liquefaction),
                                .correlation = std::string(to_string(m.liquefaction.correlation)),
                                .residual_strength_min = std::numeric_limits<double>::infinity()});
  }
  return row_of;
}

/// Marks particle p liquefied, counts it in its material's row and, for a material with
/// a residual strength, writes the record of its undrained strength.
void liquefy(const Material& m, std::size_t p, Particles& particles,
             PoreWaterReport::Material& row) {
  particles.liquefied[p] = 1;
  ++row.liquefied;
  row.liquefied_area += particles.volume[p];
  if (!has_residual_strength(m)) return;
  const double sigma_v0 = particles.initial_vertical_effective_stress[p];
  const auto strength = liquefaction::undrained_strength(m.liquefaction, sigma_v0);
  const std::span<Vec4> records = particles.surface_stress.of(p);
  if (records.empty()) throw Error("transfer: no record for the residual strength of {}", m.name);
  records.front() =
      liquefaction::make_record(strength, particles.state[p].plastic_shear_strain, sigma_v0);
  row.residual_strength_min = std::min(row.residual_strength_min, strength.residual);
  row.residual_strength_max = std::max(row.residual_strength_max, strength.residual);
}

}  // namespace

void carry_pore_water(const FemCheckpoint& fem, const MaterialTable& materials,
                      const std::vector<bool>& assumed, std::span<const Vec2> xi,
                      std::span<const std::size_t> source, Particles& particles,
                      PoreWaterReport& report) {
  const std::size_t count = particles.count();
  particles.use_pore_water_fields();
  interpolate_static_pressure(fem, xi, particles);
  auto at_source = [&](const std::vector<double>& field, std::size_t p) {
    return field.empty() ? 0.0 : field[source[p]];
  };
  report.saturated = true;
  const std::vector<std::ptrdiff_t> row_of = report_rows(materials, assumed, report);
  CompensatedSum pore_force;
  for (std::size_t p = 0; p < count; ++p) {
    particles.initial_vertical_effective_stress[p] =
        at_source(fem.initial_vertical_effective_stress, p);
    if (cap_excess(particles, p)) ++report.capped_excess;
    particles.initial_mean_effective_stress[p] = at_source(fem.initial_mean_effective_stress, p);
    particles.max_pore_pressure_ratio[p] = at_source(fem.max_pore_pressure_ratio, p);
    pore_force.add(particles.pore_pressure[p] * particles.volume[p]);
    if (particles.pore_pressure[p] != 0.0) ++report.saturated_particles;
    report.max_pore_pressure_ratio =
        std::max(report.max_pore_pressure_ratio, particles.max_pore_pressure_ratio[p]);
    const auto id = static_cast<std::size_t>(particles.material_id[p]);
    if (row_of[id] < 0) continue;
    const Material& m = materials[id];
    auto& row = report.materials[static_cast<std::size_t>(row_of[id])];
    ++row.particles;
    if (!assumed[id] &&
        !liquefaction::is_liquefied(m.liquefaction, particles.max_pore_pressure_ratio[p],
                                    particles.eps_q[p])) {
      continue;
    }
    liquefy(m, p, particles, row);
  }
  for (auto& row : report.materials) {
    if (row.liquefied == 0) row.residual_strength_min = row.residual_strength_max = 0.0;
  }
  report.pore_force_fe = fe_pore_force(fem);
  report.pore_force_particles = pore_force.value();
}

}  // namespace slide::transfer
