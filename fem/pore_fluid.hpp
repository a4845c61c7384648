// Pore water in the FE phase: saturated soil as an explicit u–p mixture (docs/method.md §10).
//
// Unknowns: the nodal displacement u of the mixture and the nodal pore pressure p
// (compression positive) on the nodes of saturated elements. The soil models see the
// effective stress σ′ (stored at the Gauss points); the total stress is σ = σ′ − p m,
// m = (1, 1, 1, 0).
//
//   mixture momentum:   M ü = f_ext − f_int(σ′) + Q p,       Q_kI = ∫ b_k N_I dA
//   fluid mass:         S ṗ = −Qᵀ u̇ − H p + f_g,             S_I = Σ (n/K_f) ∫ N_I dA (lumped)
//   with the Darcy flux n ẇ = −(k/γ_w)(∇p − ρ_w (g − ü)) (the u–p approximation: the fluid's
//   acceleration relative to the skeleton neglected), so that
//     −H p + f_g = ∫ ∇N_I · q dA,   q = −(k/γ_w)(∇p − ρ_w (g − ü)),
//   and the faces not drained are impermeable (no boundary flux).
//
// Explicit: within the central-difference step the element forces take Q p_n, and after
// the nodal update p advances by forward Euler with the new mid-step velocity:
//   p_{n+1} = p_n + dt S⁻¹ (−Qᵀ v_{n+1/2} − H p_n + f_g(a_{n})),
// the same staggering as σ′ (which also advances with v_{n+1/2}). Undrained, this is an
// extra bulk modulus K_f/n of the element, so the Courant step uses the undrained P-wave
// speed (ElementConstants::wave_speed); the Darcy term is forward Euler on a diffusion
// equation, stable for dt ≤ h²/(4D), D = (k/γ_w) K_f/n (pore_fluid_time_step).
//
// Stabilisation of equal-order u–p (docs/method.md §10, candidate (a)): the storage is
// lumped and the coupling integrated at the element's own Gauss points, so that undrained
// each node's ṗ is −(K_f/n) times the average of the adjacent Gauss points' volumetric
// strain rates, weighted by ∫N_I: nodal averaging. The Darcy term is integrated with the
// element shape's full rule (2×2 on quads): with one point a chequerboard of p would carry
// no flux and diffuse never.
//
// Held (prescribed) nodes: nodes of no saturated element, nodes on or above the water
// table (p = p_h ≤ 0 there: the suction of the linear hydrostatic field, so that an element the
// table crosses is at rest exactly) and nodes of drained node sets (p = p_h). Every other
// node is free; p never falls below the fluid's tension limit (clamped, and counted).
#pragma once

#include <cstddef>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "fem/fem_model.hpp"

namespace slide::fem {

/// Fills model.fluid's per-element, per-flux-point and per-node tables from a model whose
/// masses, densities and fluid constants (density, K_f, level, gravity) are set; `drained`
/// names node sets that keep their hydrostatic pressure. Throws Error for a drained set
/// the mesh does not have, or when no element is saturated.
void make_pore_fluid(FemModel& model, std::span<const std::string> drained);

/// Adds to each element's nodal forces the pore pressure's share Q p: f_k += Σ_gp w b_k p(gp),
/// on the saturated elements.
void add_pore_pressure_forces(const FemModel& model, const ElementGeometry& geometry,
                              std::span<const double> pore_pressure, std::span<Vec2> element_force);

/// What one pore-pressure update did.
struct PorePressureStep {
  std::size_t clamped = 0;  ///< free nodes held at the tension limit
};

/// p_{n+1} from p_n, the mid-step velocities and the accelerations in `state` over `dt`
/// (the rates go through `rate`, a scratch of the node count).
PorePressureStep advance_pore_pressure(const FemModel& model, const ElementGeometry& geometry,
                                       double dt, FemState& state, std::vector<double>& rate);

/// Tied side pairs (the free-field columns of a shaken stage, fem/seismic_boundary.hpp)
/// share their pore pressure as they share their motion: the storage-weighted mean of the
/// pair, or the held value when one of them is held.
void tie_pore_pressure(const FemModel& model, std::span<const std::pair<Index, Index>> tied,
                       FemState& state);

/// The step of the Darcy term's forward Euler, min_e h_e²/(4 D_e) with
/// D_e = max(k_x, k_y)/γ_w · K_f/n_e and h_e the element's Courant length (infinite
/// without saturated elements or without flow).
double pore_fluid_time_step(const FemModel& model);

/// σ′v0 below which a point's pore-pressure ratio is reported as 0: at the top of a
/// deposit σ′v0 → 0 and the ratio of two small numbers says nothing.
inline constexpr double min_ratio_stress = 1e3;  // Pa

/// r_u per element, the mean over its Gauss points (pore_pressure_ratio).
std::vector<double> element_pore_pressure_ratio(const FemModel& model,
                                                std::span<const double> gauss_ratio);

/// Δp = p − p_static at every node (empty for a dry state).
std::vector<double> excess_pore_pressure(const FemState& state);

/// The pore-pressure ratio r_u = Δp/σ′v0 at each Gauss point, Δp = p − p_static
/// interpolated like p, σ′v0 the state's initial_vertical_effective_stress (0 in dry
/// elements and where σ′v0 < min_ratio_stress).
void pore_pressure_ratio(const FemModel& model, const FemState& state, std::vector<double>& out);

/// An element's pore pressure and pore-pressure ratio, the means over its Gauss points of
/// p and of r_u (both 0 for a dry element).
struct ElementPoreWater {
  double pressure = 0.0;  ///< Pa
  double ratio = 0.0;     ///< r_u
};
ElementPoreWater element_pore_water(const FemModel& model, const FemState& state, Index e);

/// The pore pressure at each Gauss point, p(gp) = Σ_k N_k(gp) p_k (0 in dry elements).
void gauss_point_pressure(const FemModel& model, std::span<const double> pore_pressure,
                          std::vector<double>& out);

}  // namespace slide::fem
