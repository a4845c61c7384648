// The transfer report: what fem2mpm prints and writes next to the particle file
// (PARTICLES.h5 → PARTICLES.transfer.json). It lets a user check that the particles are
// the FE model: conserved totals (mass exactly, volume exactly), momentum and kinetic
// energy before and after, and how well the Gauss-point fields were interpolated.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "common/base/types.hpp"

namespace slide::transfer {

/// The saturated soil's share of a transfer (docs/method.md §10): the pore pressure
/// carried and the particles that liquefied, per material.
struct PoreWaterReport {
  bool saturated = false;  ///< the FE model had pore water
  std::size_t saturated_particles = 0;
  /// ∫ p dA of the FE state (the element pore pressures on the deformed volumes) and
  /// Σ p_p V_p of the particles, N/m: equal for a linear p field.
  double pore_force_fe = 0.0;
  double pore_force_particles = 0.0;
  double max_pore_pressure_ratio = 0.0;  ///< largest r_u,max of any particle
  std::size_t capped_excess = 0;         ///< particles whose Δp was capped at σ′v0
  struct Material {
    std::string name;
    std::string rule;  ///< e.g. "r_u,max ≥ 0.7 or γ ≥ 0.08"
    std::string correlation;
    std::size_t particles = 0;
    std::size_t liquefied = 0;
    double liquefied_area = 0.0;  ///< Σ V_p of the liquefied particles, m²
    double residual_strength_min = 0.0, residual_strength_max = 0.0;  ///< S_r, Pa
  };
  std::vector<Material> materials;  ///< those with a liquefaction rule
};

struct TransferReport {
  std::string input;   ///< FE checkpoint path ("" when transferred in memory)
  std::string output;  ///< particle file path
  std::string case_name;
  double time = 0.0;  ///< t_T, s

  std::string element_type;  ///< "quad4-1gp", …
  std::size_t elements = 0;
  std::size_t gauss_points = 0;
  std::size_t particles = 0;
  std::string particles_per_element;  ///< "4x4" or "16"
  std::string particle_rule;          ///< e.g. "4x4 Gauss–Legendre"

  std::string stress_interpolation;  ///< "rbf", "rbf-local" or "element"
  std::string rbf_polynomial;        ///< "none" or "linear" ("" for element)
  double rbf_shape = 0.0;            ///< c, m (0: not used)
  int rbf_neighbours = 0;            ///< k (0: not used)
  /// 1-norm condition estimate of the RBF system (rbf-local: the worst neighbourhood);
  /// 0 when no system was solved.
  double condition_estimate = 0.0;
  std::size_t factorisations = 0;
  std::size_t reduced_polynomial = 0;  ///< systems with collinear centres (linear → constant)

  /// Interpolant minus data at the Gauss points: stress in Pa; `residual_relative_max` is
  /// the largest residual of any component over that component's largest |value|.
  double residual_stress_max = 0.0;
  double residual_stress_rms = 0.0;
  double residual_relative_max = 0.0;

  // Conservation (per metre out of plane).
  double mass_fe = 0.0;           ///< Σ_e ρ V_0^e, kg/m
  double mass_particles = 0.0;    ///< Σ_p M_p
  double volume_fe = 0.0;         ///< Σ_e V_t^e, m³/m (deformed)
  double volume_particles = 0.0;  ///< Σ_p V_p
  /// Linear momentum (kg·m/s per m) and kinetic energy (J/m): FE with the lumped nodal
  /// masses, FE with element masses and mean nodal velocities (docs/method.md §3), particles.
  Vec2 momentum_fe_nodal = Vec2::Zero();
  Vec2 momentum_fe_element = Vec2::Zero();
  Vec2 momentum_particles = Vec2::Zero();
  double kinetic_energy_fe_nodal = 0.0;
  double kinetic_energy_fe_element = 0.0;
  double kinetic_energy_particles = 0.0;

  /// Elements inverted at t_T, transferred because of --allow-inverted.
  std::vector<Index> inverted_elements;
  /// Collapsed elements (inverted, or V_t^e < collapsed_volume_ratio · V_0^e) and the
  /// Gauss points they kept out of the RBF centres (0 for the element baseline).
  double collapsed_volume_ratio = 0.0;
  std::size_t collapsed_elements = 0;
  std::size_t excluded_gauss_points = 0;
  /// Particles whose interpolated accumulated plastic shear strain came out negative
  /// (RBF undershoot) and was set to zero.
  std::size_t clamped_plastic_strain = 0;
  /// Particles with an RBF value limited to its element patch's range (overshoot).
  std::size_t limited_particles = 0;
  /// Of those, the particles with a limited stress component.
  std::size_t limited_stress_particles = 0;

  PoreWaterReport pore_water;

  double seconds_interpolation = 0.0;
  double seconds_total = 0.0;
};

/// Multi-line text for the console (each line without the program prefix).
std::vector<std::string> format_report_lines(const TransferReport& report);
/// What the user must not miss (inverted, collapsed elements, limited stresses), one
/// warning per line; empty for a clean transfer.
std::vector<std::string> report_warnings(const TransferReport& report);
/// The same as a JSON object (non-finite numbers become null).
std::string report_json(const TransferReport& report);
/// PARTICLES.h5 → PARTICLES.transfer.json (any other name: name + ".transfer.json").
std::filesystem::path report_path(const std::filesystem::path& particle_file);

}  // namespace slide::transfer
