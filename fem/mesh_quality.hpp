// Mesh quality, energies and the recommended transfer zone (docs/method.md §3).
//
//  - |J_t|/|J_0| of an element: det J of the isoparametric map at the element centre on
//    the current coordinates over the same on the reference coordinates (< 0: inverted).
//  - εq of an element: the mean over its Gauss points of εq = sqrt(2/3 e:e) of the total
//    strain since t = 0.
//  - The scaled Jacobian of an element (common/geometry/element.hpp): the minimum over its corners
//    of det[e1 e2]/(|e1||e2|) (÷ sin 60° for triangles). |J_t|/|J_0| sees volume change
//    only; plastic flow is nearly isochoric, so under updated-Lagrangian kinematics an
//    element can shear flat with |J_t|/|J_0| ≈ 1, and the corner angles show it.
//  - Inverted: det J < 0 at a corner or zero area (is_inverted, as fem2mpm counts them).
//  - Summaries over the mesh: (|J_t|/|J_0|)_min over all elements; (|J_t|/|J_0|)_avg and
//    εq,avg over the "deformed" elements, those with εq > 3 %; εq,max; the number of
//    elements with a Gauss point that yielded in the last update; the area ratio
//    Σ_e V_t^e / Σ_e V_0^e (signed current areas, so a folded element subtracts its
//    area: under small strain the mesh loses area in large rotations); the scaled
//    Jacobian's minimum over all elements and its mean over the deformed ones; the
//    number of inverted elements. With no deformed element the averages are undefined:
//    they are NaN (written "nan" in the history) and the state counts as inside the
//    recommended zone, since no element has deformed enough to matter.
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
/// The recommended transfer zone of docs/method.md §3.
inline constexpr double zone_jacobian_ratio_avg_min = 0.97;
inline constexpr double zone_eps_q_avg_max = 0.20;

struct ElementQuality {
  std::vector<double> jacobian_ratio;   ///< per element
  std::vector<double> scaled_jacobian;  ///< per element: minimum over its corners
  std::vector<double> volume;           ///< per element: signed current area V_t^e, m²
  std::vector<double> eps_q;            ///< per element: mean of its Gauss points
  std::vector<double> gauss_eps_q;      ///< per Gauss point
  std::vector<std::uint8_t> yielded;    ///< per element: a Gauss point yielded last update
  std::vector<std::uint8_t> inverted;   ///< per element: is_inverted on the current nodes
  double volume_reference_total = 0.0;  ///< Σ_e V_0^e, m²
};

ElementQuality evaluate_quality(const FemModel& model, const FemState& state,
                                std::span<const Vec2> coordinates);

struct QualitySummary {
  double jacobian_ratio_min = 1.0;
  double jacobian_ratio_avg = 0.0;  ///< NaN without deformed elements
  double eps_q_avg = 0.0;           ///< NaN without deformed elements
  double eps_q_max = 0.0;
  Index n_elements_yielding = 0;
  double area_ratio = 1.0;           ///< Σ V_t / Σ V_0 (NaN without reference area)
  double scaled_jacobian_min = 1.0;  ///< over all elements
  double scaled_jacobian_avg = 0.0;  ///< NaN without deformed elements
  Index n_elements_deformed = 0;     ///< εq > 3 %
  Index n_elements_inverted = 0;
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
