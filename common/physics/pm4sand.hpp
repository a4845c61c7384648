// PM4Sand, a bounding-surface plasticity model for sands in plane strain that liquefies:
// version 3.1 of Boulanger & Ziotopoulou (2017), written out with its sources in
// common/physics/constitutive.md ("PM4Sand") and docs/method.md §10.
//
// The model works in the plane: p = (σxx + σyy)/2 and the in-plane deviator, compression
// positive (the reference implementations' convention), while the rest of the library is
// tension positive; the conversion happens at this interface. σzz takes no part in the
// model: it is kept at the in-plane mean (σzz = (σxx + σyy)/2), so the three-dimensional
// mean stress equals the model's p (a documented choice: docs/method.md §10).
//
// Per point the model carries ten records of four numbers (the per-point records of
// common/physics/material_state.hpp, dataset state/surface_stress): eight tensors as
// [xx, yy, 0, xy] (so that the objective rotation turns them like the stress), then the
// scalars. Their layout is `Record` below and the schema page's table.
#pragma once

#include <array>
#include <cmath>
#include <span>

#include "common/base/types.hpp"
#include "common/physics/material.hpp"
#include "common/physics/material_state.hpp"

namespace slide::pm4sand {

/// Number of four-number records per point.
inline constexpr int records = 10;

/// The records of one point, in order.
enum Record : int {
  back_stress = 0,         ///< α, the back-stress ratio
  apparent_reversal = 1,   ///< α_in, the apparent back-stress ratio at the last reversal
  previous_reversal = 2,   ///< α_in,p, the apparent one of the reversal before
  true_reversal = 3,       ///< α_in,true, α at the last reversal
  reversal_maximum = 4,    ///< α_in,max, the largest negative components seen at reversals
  reversal_minimum = 5,    ///< α_in,min, the smallest positive components seen at reversals
  fabric = 6,              ///< z, the fabric tensor
  fabric_at_reversal = 7,  ///< z_in, z at the last reversal
  fabric_measures = 8,     ///< [z_cum, z_peak, p_zp, z_xp]
  switch_constants = 9,    ///< [z_max, A_do, p_min, ε_v since the switch]
};

/// The model's constants: the material's parameters with every secondary one resolved
/// (defaults from D_R), in Pa and radians-free ratios. z_max and A_do are NaN when they
/// depend on the point's stress at the switch (their defaults).
struct Constants {
  double relative_density;   // D_R at the switch
  double g0;                 // G₀
  double h_po;               // contraction rate
  double p_a;                // atmospheric pressure, Pa
  double h0;                 // plastic modulus ratio
  double e_max, e_min, e0;   // void ratios (e0 from D_R)
  double n_b, n_d;           // bounding and dilatancy exponents
  double a_do;               // dilatancy constant (NaN: from the switch)
  double z_max;              // largest fabric (NaN: from the switch)
  double c_z, c_e;           // fabric growth, fabric erasure
  double m_c;                // critical ratio 2 sin φ_cv
  double nu;                 // Poisson's ratio of the elastic response
  double c_gd, c_dr, c_kaf;  // fabric's degradation of G, rotated dilatancy, C_kα
  double q, r;               // critical state line (Bolton): D_R,cs = R/(Q − ln(100 p/p_A))
  double m;                  // yield surface size
  double strain_step;        // largest strain component of one sub-increment

  static Constants of(const Material& material);
  /// Bulk modulus over shear modulus, 2(1 + ν)/(3(1 − 2ν)).
  double bulk_ratio() const { return 2.0 * (1.0 + nu) / (3.0 * (1.0 - 2.0 * nu)); }
};

/// The report's field correlation (N1)60 = 46 D_R², and its inverse.
inline double blow_count(double relative_density) {
  return 46.0 * relative_density * relative_density;
}
inline double relative_density_of(double n160) {
  return std::sqrt(n160 / 46.0);
}

/// The shear modulus coefficient's field default, G₀ = 167 sqrt((N1)60 + 2.5).
double default_shear_modulus_coefficient(double relative_density);

/// G₀ from the overburden-corrected shear-wave speed V_s1 (m/s at σ′v = 1 atm) and the
/// soil's density: G = ρ V_s1² at p ≈ p_A, so G₀ = ρ V_s1²/p_A.
inline double shear_modulus_coefficient_from_wave_speed(double density, double vs1,
                                                        double atmospheric_pressure) {
  return density * vs1 * vs1 / atmospheric_pressure;
}

/// The Young's modulus of PM4Sand's elastic (geostatic) stage, whose shear modulus is
/// G₀ p_A (the reference implementations' elastic stage): E = 2 (1 + ν) G₀ p_A.
double elastic_stage_youngs_modulus(const Material& material);

/// Sets up a point at the switch from the elastic stage (the stress, tension positive,
/// is the point's stress then): α = s/p, the stress-dependent constants z_max, A_do and
/// p_min from p₀, fabric zero. A stress ratio beyond the bounding and dilatancy ratios is
/// brought back to the larger of them, and an unconfined point (p₀ < p_min) set to p_min:
/// then returns true. σzz is set to the in-plane mean (not counted as a change). A point
/// whose records are already set (p_min > 0) keeps them.
bool start(const Constants& c, Vec4& stress, std::span<Vec4> point);

/// One strain increment [Δεxx, Δεyy, Δεzz (ignored: plane strain), Δγxy], tension positive.
/// Explicit integration in sub-increments of at most `strain_step`, each by modified
/// Euler with error control and a drift correction back to the yield surface. Adds the
/// plastic strains to `state`; returns true when the point loaded plastically.
bool update(const Constants& c, Vec4& stress, MaterialState& state, const Vec4& strain_increment,
            std::span<Vec4> point);

/// The objective rotation of the tensor records by a spin increment (the stress is
/// rotated by the caller).
void rotate(std::span<Vec4> point, double spin_increment);

/// Elastic shear modulus at the state of a point (G = G₀ p_A sqrt(p/p_A) C_SR fabric
/// factor), Pa; before the switch (records unset) G₀ p_A sqrt(p/p_A).
double shear_modulus(const Constants& c, const Vec4& stress, std::span<const Vec4> point);

/// The stress ratio q/p = sqrt(2) |s|/p of the in-plane stress, and the bounding and
/// dilatancy ratios M_b, M_d at mean stress p and relative density D_R.
double stress_ratio(const Vec4& stress);
struct Ratios {
  double bounding;
  double dilatancy;
  double state_parameter;  ///< ξ_R = R/(Q − ln(100 p/p_A)) − D_R
};
Ratios ratios(const Constants& c, double mean_stress, double relative_density);

/// The relative density of a point now (its void ratio has changed by its volumetric
/// strain since the switch).
double relative_density(const Constants& c, std::span<const Vec4> point);

}  // namespace slide::pm4sand
