// Mesh quality, energies and the recommended transfer zone (METHOD.md §3).
//
//  - |J_t|/|J_0| of an element: det J of the isoparametric map at the element centre on
//    the current coordinates over the same on the reference coordinates (< 0: inverted).
//  - εq of an element: the mean over its Gauss points of εq = sqrt(2/3 e:e) of the total
//    strain since t = 0.
//  - Summaries over the mesh: (|J_t|/|J_0|)_min over all elements; (|J_t|/|J_0|)_avg and
//    εq,avg over the "deformed" elements, those with εq > 3 %; εq,max; the number of
//    elements with a Gauss point that yielded in the last update. With no deformed
//    element the two averages are undefined: they are NaN (written "nan" in the
//    history) and the state counts as inside the recommended zone, since no element
//    has deformed enough to matter.
//  - Recommended transfer zone: (|J_t|/|J_0|)_avg ≥ 0.97 and εq,avg ≤ 0.20.
//  - Energies (J per m): KE = Σ_e ½ m_e |v̄_e|² with v̄_e the mean velocity of the
//    element's nodes; PE = Σ_e m_e g h_e with h_e the mean current elevation of its
//    nodes (PE_0 is PE at t = 0); stored elastic energy Σ_gp ½ σ:C⁻¹:σ w (3-D isotropic
//    compliance on the full plane-strain stress, so σzz counts); hourglass energy
//    Σ_e ½ Qᵀ K_q⁻¹ Q. The weights w and K_q are those the kernels use: reference for
//    small strain, current for updated Lagrangian.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "fem/fem_model.hpp"

namespace slide::fem {

/// Elements count as deformed, and enter the averages, above this εq.
inline constexpr double deformed_eps_q = 0.03;
/// The recommended transfer zone of METHOD.md §3.
inline constexpr double zone_jacobian_ratio_avg_min = 0.97;
inline constexpr double zone_eps_q_avg_max = 0.20;

struct ElementQuality {
  std::vector<double> jacobian_ratio;  ///< per element
  std::vector<double> volume;          ///< per element: signed current area V_t^e, m²
  std::vector<double> eps_q;           ///< per element: mean of its Gauss points
  std::vector<double> gauss_eps_q;     ///< per Gauss point
  std::vector<std::uint8_t> yielded;   ///< per element: a Gauss point yielded last update
};

ElementQuality evaluate_quality(const FemModel& model, const FemState& state,
                                std::span<const Vec2> coordinates);

struct QualitySummary {
  double jacobian_ratio_min = 1.0;
  double jacobian_ratio_avg = 0.0;  ///< NaN without deformed elements
  double eps_q_avg = 0.0;           ///< NaN without deformed elements
  double eps_q_max = 0.0;
  Index n_elements_yielding = 0;
  Index n_elements_deformed = 0;  ///< εq > 3 %
};

QualitySummary summarise(const ElementQuality& quality);

/// Inside the recommended transfer zone (true when no element is deformed yet).
bool inside_recommended_zone(const QualitySummary& summary);

struct Energies {
  double kinetic = 0.0;
  double potential = 0.0;  ///< absolute, Σ m_e g h_e
  double elastic = 0.0;
  double hourglass = 0.0;
};

/// Energies of the state with nodal velocities `velocity` (normally the synchronised
/// velocity) on the current `coordinates`, integrated with `geometry`.
Energies compute_energies(const FemModel& model, const ElementGeometry& geometry,
                          const FemState& state, std::span<const Vec2> velocity,
                          std::span<const Vec2> coordinates);

/// Σ_e m_e g (h_e − y_min) on the reference coordinates: the potential energy the body
/// could release by falling to its lowest point, the scale of the energy guard.
double releasable_potential_energy(const FemModel& model);

}  // namespace slide::fem
