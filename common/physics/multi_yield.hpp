// Pressure-independent multi-yield plasticity (docs/method.md §3): the FE material of the
// reference workflow (OpenSees's PressureIndependMultiYield, calibrated to Mohr–Coulomb),
// written out with its sources in common/physics/constitutive.md.
//
// Volumetric response linear elastic, Δp = −K Δεv; deviatoric response elastoplastic
// with von Mises surfaces and no tension cut-off. The peak strength is frozen at the
// switch from the point's own mean effective stress p′₀ (compression positive):
//   q_f = M p′₀ + q₀,  M = 6 sin φ / (3 − sin φ),  q₀ = 3c/√2   (φ > 0)
//   q_f = 2c                                                  (φ = 0)
// (OpenSees: the failure surface's size M (p′₀ + p_r) with the "residual pressure"
// p_r = 3c/(√2 M); q is the von Mises stress sqrt(3/2 s:s)). A later change of
// confinement leaves q_f unchanged.
//
// The backbone is OpenSees's: the hyperbola τ = G γ / (1 + γ/γ_r) in octahedral shear
// stress and strain (τ = √2/3 q, γ = √2 εq), γ_r such that τ(γ_peak) = τ_f, sampled at
// τ_i = i τ_f / N (i = 1 … N): elastic with G up to τ_1, then the hyperbola's secant
// slope between τ_i and τ_{i+1} while the stress lies between them, perfectly plastic
// at τ_f. Its vertices sit at γ̃_i = τ_1/G + γ_i − γ_1, γ_i the hyperbola's strain at τ_i.
//
// Kinematic hardening in the overlay (parallel, Iwan 1967) form of the nested-surface
// model: the deviatoric stress is the sum s = Σ s_i of N elastic–perfectly-plastic
// von Mises components that share the strain, component i with modulus 2G_i and yield
// stress k_i (q units), G_i and k_i chosen so that under monotonic loading component i
// reaches its limit exactly at vertex i:
//   G_i = S_{i−1} − S_i (S_0 = G, S_i the slope after vertex i, S_N = 0),  k_i = 3/√2 G_i γ̃_i.
// Each component's update is an exact radial return, so the model has no drift, unloads
// elastically with G, follows Masing's rule on reversal, and with N = 1 is exactly
// elastic–perfectly-plastic von Mises. The i-th "surface" of the nested form is the set
// of stresses at which component i starts to flow; OpenSees translates its surfaces
// with Prevost's (Mróz-type) rule instead, which gives the same backbone and the same
// Masing loops on proportional paths and differs on non-proportional ones.
#pragma once

#include <array>
#include <cmath>
#include <limits>
#include <span>

#include "common/base/types.hpp"
#include "common/physics/material.hpp"
#include "common/physics/material_state.hpp"

namespace slide::multi_yield {

/// The backbone of one point as its N components: 2G_i (Pa) and k_i (Pa, von Mises).
struct Components {
  int count = 0;
  std::array<double, max_yield_surfaces> two_shear;  ///< the first `count` are set
  std::array<double, max_yield_surfaces> limit;
  std::array<double, max_yield_surfaces> limit_squared;  ///< k_i², the update's yield test
};

/// A point's components kept between its updates (FE Gauss points: ExplicitSolver keeps
/// one per point). They depend on the model's G, γ_peak and N, fixed for a point, and on
/// the point's frozen peak strength q_f, which they are tagged with: a point whose q_f
/// is not the tag's (the first update, a switch) has them computed again. Computing them
/// costs about as much as the update itself (20 surfaces: ~600 instructions).
struct KeptComponents {
  double peak_strength = std::numeric_limits<double>::quiet_NaN();  ///< q_f they are for
  Components components;
};

/// The components of a point with peak strength `peak_strength` (q_f, Pa) for shear
/// modulus G, octahedral peak strain γ_peak and N surfaces. When τ_f ≥ G γ_peak (no
/// hyperbola with that peak strain exists) the backbone is elastic–perfectly plastic:
/// the last component carries all of G. q_f ≤ 0 gives a point without shear strength.
Components components(double shear_modulus, double peak_strength, double peak_shear_strain,
                      int count);

/// One strain increment: every component's elastic predictor and radial return, the
/// stress rebuilt as Σ s_i + mean stress. Accumulates the deviatoric plastic strain
/// Δeᵖ = Δe − Δs/(2G) in state.plastic_shear_strain. Returns true when the last
/// component is at its limit (the point is at its peak strength).
bool update(const Components& c, double bulk_modulus, double shear_modulus, Vec4& stress,
            MaterialState& state, const Vec4& strain_increment, std::span<Vec4> surfaces);

/// Sets the components as after a monotonic proportional loading from zero to the
/// deviatoric part of `stress` (scaled down to q_f when it lies outside; then returns
/// true). The mean stress is kept.
bool load_monotonically(const Components& c, Vec4& stress, std::span<Vec4> surfaces);

/// A state carried over from elsewhere (another phase, an interpolation): each component
/// is brought back onto its limit if it lies outside, and the deviatoric stress becomes
/// their sum. Returns true when the stress changed by more than round-off.
bool reconcile(const Components& c, Vec4& stress, std::span<Vec4> surfaces);

/// The von Mises stress q = sqrt(3/2 s:s) of a deviatoric tensor [sxx, syy, szz, sxy].
inline double von_mises(const Vec4& s) {
  return std::sqrt(1.5 * (s[0] * s[0] + s[1] * s[1] + s[2] * s[2] + 2.0 * s[3] * s[3]));
}

}  // namespace slide::multi_yield
