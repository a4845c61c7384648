#include "fem/mesh_quality.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "common/physics/constitutive.hpp"

namespace slide::fem {

ElementQuality evaluate_quality(const FemModel& model, const FemState& state,
                                std::span<const Vec2> coordinates) {
  const Mesh& mesh = model.mesh;
  const auto n_elements = static_cast<std::size_t>(mesh.element_count());
  const auto n_gauss = static_cast<std::size_t>(model.gauss_per_element());
  const Vec2 centre = reference_centre(mesh.shape());
  ElementQuality quality;
  quality.jacobian_ratio.assign(n_elements, 0.0);
  quality.scaled_jacobian.assign(n_elements, 0.0);
  quality.volume.assign(n_elements, 0.0);
  quality.eps_q.assign(n_elements, 0.0);
  quality.gauss_eps_q.assign(n_elements * n_gauss, 0.0);
  quality.yielded.assign(n_elements, 0);
  quality.inverted.assign(n_elements, 0);
  for (std::size_t e = 0; e < n_elements; ++e) {
    const ElementNodes x = mesh.element_nodes(static_cast<Index>(e), coordinates);
    quality.jacobian_ratio[e] =
        jacobian(mesh.shape(), x, centre).determinant() / model.elements.centre_det_reference[e];
    quality.scaled_jacobian[e] = scaled_jacobian(mesh.shape(), x);
    quality.inverted[e] = is_inverted(mesh.shape(), x) ? 1 : 0;
    quality.volume[e] = element_area(mesh.shape(), x);
    quality.volume_reference_total += model.elements.volume_reference[e];
    double sum = 0.0;
    std::uint8_t yielded = 0;
    for (std::size_t p = 0; p < n_gauss; ++p) {
      const std::size_t gp = e * n_gauss + p;
      quality.gauss_eps_q[gp] = deviatoric_strain(state.strain[gp]);
      sum += quality.gauss_eps_q[gp];
      yielded |= state.yielded[gp];
    }
    quality.eps_q[e] = sum / static_cast<double>(n_gauss);
    quality.yielded[e] = yielded;
  }
  return quality;
}

QualitySummary summarise(const ElementQuality& quality) {
  QualitySummary summary;
  summary.jacobian_ratio_min = std::numeric_limits<double>::infinity();
  summary.scaled_jacobian_min = std::numeric_limits<double>::infinity();
  double jacobian_sum = 0.0, eps_q_sum = 0.0, scaled_sum = 0.0, volume_sum = 0.0;
  for (std::size_t e = 0; e < quality.eps_q.size(); ++e) {
    summary.jacobian_ratio_min = std::min(summary.jacobian_ratio_min, quality.jacobian_ratio[e]);
    summary.scaled_jacobian_min = std::min(summary.scaled_jacobian_min, quality.scaled_jacobian[e]);
    summary.eps_q_max = std::max(summary.eps_q_max, quality.eps_q[e]);
    summary.n_elements_yielding += quality.yielded[e];
    summary.n_elements_inverted += quality.inverted[e];
    volume_sum += quality.volume[e];
    if (quality.eps_q[e] > deformed_eps_q) {
      ++summary.n_elements_deformed;
      jacobian_sum += quality.jacobian_ratio[e];
      scaled_sum += quality.scaled_jacobian[e];
      eps_q_sum += quality.eps_q[e];
    }
  }
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const auto deformed = static_cast<double>(summary.n_elements_deformed);
  summary.jacobian_ratio_avg = summary.n_elements_deformed > 0 ? jacobian_sum / deformed : nan;
  summary.scaled_jacobian_avg = summary.n_elements_deformed > 0 ? scaled_sum / deformed : nan;
  summary.eps_q_avg = summary.n_elements_deformed > 0 ? eps_q_sum / deformed : nan;
  summary.area_ratio =
      quality.volume_reference_total > 0.0 ? volume_sum / quality.volume_reference_total : nan;
  return summary;
}

bool inside_recommended_zone(const QualitySummary& summary) {
  if (summary.n_elements_deformed == 0) return true;
  return summary.jacobian_ratio_avg >= zone_jacobian_ratio_avg_min &&
         summary.eps_q_avg <= zone_eps_q_avg_max;
}

Energies compute_energies(const FemModel& model, const ElementGeometry& geometry,
                          const FemState& state, std::span<const Vec2> velocity,
                          std::span<const Vec2> coordinates) {
  const Mesh& mesh = model.mesh;
  const auto n_gauss = static_cast<std::size_t>(model.gauss_per_element());
  const double inverse_nodes = 1.0 / model.nodes_per_element;
  Energies energies;
  for (Index e = 0; e < mesh.element_count(); ++e) {
    const auto ei = static_cast<std::size_t>(e);
    Vec2 mean_velocity = Vec2::Zero();
    Vec2 mean_position = Vec2::Zero();
    for (Index node : mesh.element(e)) {
      mean_velocity += velocity[static_cast<std::size_t>(node)];
      mean_position += coordinates[static_cast<std::size_t>(node)];
    }
    mean_velocity *= inverse_nodes;
    mean_position *= inverse_nodes;
    const double mass = model.elements.mass[ei];
    energies.kinetic += 0.5 * mass * mean_velocity.squaredNorm();
    // −m g·x, written so that g = (0, −9.81) gives (m 9.81) y exactly as before.
    energies.potential += -(mass * model.gravity.y()) * mean_position.y() -
                          (mass * model.gravity.x()) * mean_position.x();
    const Material& material = model.material_of(e);
    for (std::size_t p = 0; p < n_gauss; ++p) {
      const std::size_t gp = ei * n_gauss + p;
      energies.elastic += geometry.weight[gp] * elastic_energy_density(material, state.stress[gp]);
    }
    if (model.hourglass && model.hourglass_coefficient != 0.0) {
      const Vec2& q_force = state.hourglass_force[ei];
      energies.hourglass += 0.5 * q_force.dot(geometry.hourglass_stiffness[ei].inverse() * q_force);
    }
  }
  return energies;
}

double releasable_potential_energy(const FemModel& model) {
  const Mesh& mesh = model.mesh;
  double energy = 0.0;
  for (Index e = 0; e < mesh.element_count(); ++e) {
    double mean_elevation = 0.0;
    for (Index node : mesh.element(e))
      mean_elevation += mesh.nodes[static_cast<std::size_t>(node)].y();
    mean_elevation /= model.nodes_per_element;
    energy += model.elements.mass[static_cast<std::size_t>(e)] * gravity_acceleration *
              (mean_elevation - model.extent.y_min);
  }
  return energy;
}

}  // namespace slide::fem
