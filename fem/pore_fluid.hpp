// Pore water in the FE phase: saturated soil as an explicit u–p mixture (docs/method.md §10).
//
// Unknowns: the nodal displacement u of the mixture and one pore pressure p_e per
// saturated element (compression positive), the element's centre value. The soil models
// see the effective stress σ′ (stored at the Gauss points); the total stress is
// σ = σ′ − p_e m, m = (1, 1, 1, 0).
//
//   mixture momentum:  M ü = f_ext − f_int(σ′) + Q p,   Q_ke = ∫_e b_k dA (at the element's
//                      own Gauss points)
//   fluid mass:        S_e ṗ_e = −∫_e ∇·v dA − Σ_faces F,   S_e = (n_e/K_f) A_e
//   Darcy across a face between elements a and b (two-point flux):
//                      F_ab = T_ab (φ_a − φ_b),  φ = p − ρ_w (g − a)·x,
//   T_ab the harmonic mean of the half-transmissibilities t = L (d·K n)/(d·d), K = k/γ_w,
//   d from the element's centre to the face's midpoint, n the face's normal, L its length.
//   A face is drained (p held at the hydrostatic value of its midpoint) when both its
//   nodes are held: on or above the water table, or in a drained node set; the other
//   faces without a saturated neighbour are impermeable.
//
// Explicit: within the central-difference step the element forces take Q p_n, and after
// the nodal update p advances by forward Euler with the new mid-step velocity and the
// last acceleration: p_{n+1} = p_n + dt ṗ_n — the same staggering as σ′. Undrained, this is
// an extra bulk modulus K_f/n of the element, so the Courant step uses the undrained
// P-wave speed (ElementConstants::wave_speed); the flow is forward Euler on a diffusion
// equation, stable for dt ≤ S_e/Σ_faces T (h²/(4D) on squares, D = (k/γ_w) K_f/n;
// pore_fluid_time_step).
//
// Why the element's centre (candidate (c) of docs/method.md §10): with nodal p on one-point
// quads (candidate (a), nodal averaging) each node's ṗ is the mean of the adjacent
// elements' ∇·v, a constraint per node on a smoothed volume change: alternating volume
// changes cost no fluid energy and a strip load leaves a pressure chequerboard. One p per
// element is the one volumetric constraint per element that one-point quads carry
// anyway (the figures of each candidate are in fem/README.md, "Pore water").
//
// The nodal pore pressure of the output (VTK, recorders, the checkpoint's /nodes) is the
// node's hydrostatic value plus the storage-weighted mean of the excess pressure of the
// saturated elements around it; held nodes show their hydrostatic value. p never falls below the
// fluid's tension limit (clamped, and counted).
#pragma once

#include <cstddef>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "fem/fem_model.hpp"

namespace slide::fem {

/// Fills model.fluid's per-element, per-face and per-node tables from a model whose
/// densities and fluid constants (density, K_f, level, gravity) are set; `drained` names
/// node sets that keep their hydrostatic pressure. Throws Error for a drained set the
/// mesh does not have, or when no element is saturated.
void make_pore_fluid(FemModel& model, std::span<const std::string> drained);

/// Adds to each saturated element's nodal forces the pore pressure's share Q p:
/// f_k += Σ_gp w b_k p_e.
void add_pore_pressure_forces(const FemModel& model, const ElementGeometry& geometry,
                              std::span<const double> element_pressure,
                              std::span<Vec2> element_force);

/// What one pore-pressure update did.
struct PorePressureStep {
  std::size_t clamped = 0;  ///< elements held at the tension limit
};

/// The scratch of a pore-pressure update.
struct PressureScratch {
  std::vector<double> rate;        ///< S_e ṗ_e, per element
  std::vector<Vec2> acceleration;  ///< the mean nodal acceleration, per element
};

/// p_{n+1} from p_n, the mid-step velocities and the accelerations in `state` over `dt`;
/// then the `tied` pairs of elements (the free-field columns of a shaken stage,
/// fem/seismic_boundary.hpp; empty otherwise) share their pore pressure as they share their
/// motion, the storage-weighted mean of the pair; then the nodal p of the output
/// (update_nodal_pore_pressure), once.
PorePressureStep advance_pore_pressure(const FemModel& model, const ElementGeometry& geometry,
                                       double dt, std::span<const std::pair<Index, Index>> tied,
                                       FemState& state, PressureScratch& scratch);

/// state.pore_pressure from state.element_pore_pressure: the node's hydrostatic p plus the
/// storage-weighted mean of the excess p_e − p_h(centre) of the saturated elements around
/// it (so that the hydrostatic field is exact at the nodes too); held nodes keep p_h.
void update_nodal_pore_pressure(const FemModel& model, FemState& state);

/// Each element's mean of its nodes' values.
std::vector<double> element_mean_of_nodes(const FemModel& model, std::span<const double> nodal);

/// The elements' p from a nodal p: each saturated element's mean of its nodes, 0 in dry
/// ones (a checkpoint written before elements carried p; an OpenSees u–p recorder).
std::vector<double> element_pressure_from_nodes(const FemModel& model,
                                                std::span<const double> nodal);

/// The step of the flow's forward Euler, min_e S_e/Σ_faces T (infinite without saturated
/// elements or without flow).
double pore_fluid_time_step(const FemModel& model);

/// σ′v0 below which a point's pore-pressure ratio is reported as 0: at the top of a
/// deposit σ′v0 → 0 and the ratio of two small numbers says nothing.
inline constexpr double min_ratio_stress = 1e3;  // Pa

/// r_u per element, the mean over its Gauss points (pore_pressure_ratio).
std::vector<double> element_pore_pressure_ratio(const FemModel& model,
                                                std::span<const double> gauss_ratio);

/// Δp = p − p_static at every node (empty for a dry state).
std::vector<double> excess_pore_pressure(const FemState& state);

/// The pore-pressure ratio r_u = Δp/σ′v0 at each Gauss point: Δp = p_e − the element's
/// mean of the nodal p_static, σ′v0 the state's initial_vertical_effective_stress (0 in
/// dry elements and where σ′v0 < min_ratio_stress).
void pore_pressure_ratio(const FemModel& model, const FemState& state, std::vector<double>& out);

/// An element's pore pressure and pore-pressure ratio, p_e and the mean of r_u over its
/// Gauss points (both 0 for a dry element).
struct ElementPoreWater {
  double pressure = 0.0;  ///< Pa
  double ratio = 0.0;     ///< r_u
};
ElementPoreWater element_pore_water(const FemModel& model, const FemState& state, Index e);

/// The water leaving the soil through a drained face (face.to < 0), m³/s per m: the flow
/// from its element to the face's held pressure.
double drained_outflow(const FemModel& model, const FemState& state, const FluidFace& face);

/// The pore pressure at each Gauss point, its element's p_e (0 in dry elements).
void gauss_point_pressure(const FemModel& model, std::span<const double> element_pressure,
                          std::vector<double>& out);

}  // namespace slide::fem
