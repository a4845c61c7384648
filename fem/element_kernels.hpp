// Element kernels of the FE phase: free functions over all elements, specialised at
// compile time for the three element types (quad4-1gp, quad4-2x2, tri3), with no
// allocation and no virtual call inside the element loops.
//
// Notation: b_k = ∂N_k/∂x at a Gauss point, w its weight w·det J, v_k and u_k nodal
// velocity and displacement, σ = [σxx, σyy, σzz, σxy].
//
//  - Strain increment (plane strain):
//      Δε = Δt [Σ b_kx v_kx, Σ b_ky v_ky, 0, Σ (b_ky v_kx + b_kx v_ky)].
//  - Internal force: f_k = Σ_gp w [b_kx σxx + b_ky σxy, b_ky σyy + b_kx σxy].
//  - Hourglass control of one-point quads (Flanagan & Belytschko 1981, with a physical
//    stiffness): with h = (1, −1, 1, −1) and b the gradients at the centre,
//      γ_k = ¼ [h_k − (h·x) b_kx − (h·y) b_ky],   q = Σ_k γ_k u_k,
//    q is the ξη coefficient of the displacement field once its linear part is removed
//    (γ·1 = γ·x = γ·y = 0, γ·h = 1). The strain of the mode u = q ξη is
//      ε(ξ, η) = η sym(q ⊗ ∇ξ) + ξ sym(q ⊗ ∇η),
//    and its elastic energy over the element (det J = |J_0| constant on a parallelogram,
//    ∫η² = ∫ξ² = 4/3, ∫ξη = 0) is ½ qᵀ K_q q with
//      K_q = (4/3) |J_0| Σ_{g ∈ {∇ξ, ∇η}} G_gᵀ C G_g,
//      G_g q = [g_x q_x, g_y q_y, g_y q_x + g_x q_y].
//    The generalised hourglass force is Q = K_q q and the nodal forces f_k = γ_k Q. On a
//    parallelogram the 2×2 Gauss rule integrates the same quadratic energy exactly, so
//    the stabilised one-point element has exactly the stiffness of the 2×2 element.
//    Q is accumulated incrementally, Q ← Q + K_q Δq with Δq = Σ_k γ_k Δu_k, which for
//    small strain (constant γ, K_q) is the total K_q q plus the geostatic Q, and for
//    updated Lagrangian uses the current γ and K_q.
//  - Stiffness-proportional Rayleigh damping β_K (docs/method.md §3), the force −β_K K₀ v
//    without assembling K₀: a viscous stress β_K D ε̇, ε̇ = B v, added to σ in the
//    internal force only (never stored, never seen by the constitutive model), with D the
//    initial elastic plane-strain matrix of the element's material, and for one-point
//    quads a viscous hourglass force β_K K_q q̇, q̇ = Σ_k γ_k v_k, added to Q. Then the
//    element's damping matrix is β_K times its whole stiffness (element_stiffness), the
//    hourglass part included, so every mode of frequency ω gets the damping ratio
//    ξ = β_K ω / 2. (The out-of-plane viscous stress λ (ε̇xx + ε̇yy) does no work in
//    plane strain, ε̇zz = 0, and is left out.)
#pragma once

#include <cstddef>
#include <span>

#include <Eigen/Core>

#include "common/physics/constitutive.hpp"
#include "fem/fem_model.hpp"

namespace slide::fem {

/// Evaluates `geometry` (gradients, weights, and for one-point quads γ and K_q) on
/// `coordinates`. Returns the first element with det J ≤ 0 at one of its Gauss points
/// or at its centre (an inverted or degenerate element), or −1 when there is none; the
/// geometry of an inverted element is left as computed (non-finite gradients).
Index compute_geometry(const FemModel& model, std::span<const Vec2> coordinates,
                       ElementGeometry& geometry);

/// Nodal forces of each element, −(internal + hourglass), into `element_force`
/// (n_elements × nodes_per_element, element-major): what the element pushes its nodes
/// with. With `rayleigh_stiffness` β_K > 0 (s) they include the stiffness-proportional
/// damping force −β_K K₀ v of the nodal velocities in `state` (the explicit step passes
/// the mid-step velocity v_{n−1/2}); β_K = 0 runs the undamped kernel.
void compute_element_forces(const FemModel& model, const ElementGeometry& geometry,
                            const FemState& state, std::span<Vec2> element_force,
                            double rayleigh_stiffness = 0.0);

/// Advances strain, stress, material state and hourglass forces by one step of length
/// `dt` from the nodal velocities in `state` (the mid-step velocity). With `jaumann` the
/// stress is first rotated by the spin increment (updated Lagrangian). `models` is
/// indexed by material id. Whether each Gauss point yielded goes to state.yielded.
/// `kept` (empty, or one per Gauss point): the points' multi-yield components between
/// steps (ConstitutiveModel::update).
void update_stresses(const FemModel& model, const ElementGeometry& geometry,
                     std::span<const ConstitutiveModel> models, double dt, bool jaumann,
                     FemState& state, std::span<multi_yield::KeptComponents> kept = {});

/// Elastic element stiffness (2n × 2n, DOFs ordered [u_0x, u_0y, u_1x, …]) of element
/// `e`: Σ_gp w Bᵀ C B plus, for one-point quads, the hourglass stiffness γγᵀ ⊗ K_q.
using ElementMatrix = Eigen::Matrix<double, 2 * max_nodes_per_element, 2 * max_nodes_per_element>;
ElementMatrix element_stiffness(const FemModel& model, const ElementGeometry& geometry, Index e);

/// Stable time step of the Courant condition, dt = C·min_e(l_e / c_p), with l_e the area
/// over the longest edge (quads) or twice the area over the longest edge (triangles) on
/// `coordinates`, and c_p the element's P-wave speed (ElementConstants::wave_speed:
/// undrained in a saturated element).
double courant_time_step(const FemModel& model, std::span<const Vec2> coordinates, double courant);
/// The same with the given per-element speeds (e.g. ElementConstants::skeleton_wave_speed).
double courant_time_step(const FemModel& model, std::span<const Vec2> coordinates, double courant,
                         std::span<const double> wave_speed);

/// Stable step with stiffness-proportional Rayleigh damping β_K (s), from the Courant step
/// at C = 1, dt_c = min_e(l_e / c_p) (`critical_step`), and the Courant number C.
///
/// The explicit step damps with the velocity of the previous half step. For one mode of
/// frequency ω and damping c = α_M + β_K ω² that is
///   v⁺ = (1 − c dt) v⁻ − ω² dt u,   u⁺ = u + dt v⁺,
/// i.e. u⁺ − (2 − c dt − ω² dt²) u + (1 − c dt) u⁻ = 0, whose roots lie in the unit circle
/// while ω² dt² + 2 c dt ≤ 4: dt ≤ (2/ω)(sqrt(1 + ξ²) − ξ), ξ = c/(2ω) the mode's damping
/// ratio. The stiffness term makes ξ grow with ω, so the highest frequency of the mesh,
/// ω_max = 2/dt_c, sets the step:
///   dt = C dt_c (sqrt(1 + ξ_max²) − ξ_max),   ξ_max = β_K ω_max / 2 = β_K / dt_c,
/// evaluated as C dt_c / (sqrt(1 + ξ_max²) + ξ_max), which does not cancel at large ξ_max
/// (where dt → C dt_c / (2 ξ_max) = C dt_c² / (2 β_K)). β_K = 0 gives C dt_c exactly.
/// (The mass term's α_M/(2 ω_max) is small, 1.1e-3 for column-short at ξ = 5 % at 1 and
/// 10 Hz, and is left to C ≤ 0.5.)
double damped_time_step(double critical_step, double courant, double rayleigh_stiffness);

/// The same when the damped stiffness is not all of the stiffness: with pore water the
/// viscous stress β_K D ε̇ acts on the skeleton, while the highest frequency comes from
/// the water's bulk modulus in the undrained P wave. Per mode the condition is
/// ω² dt² + 2 c dt ≤ 4 with c = β_K k_s/m ≤ β_K ω_s,max², ω_s,max = 2/dt_c,s the highest
/// frequency of the skeleton alone (`skeleton_step`, the Courant step with
/// ElementConstants::skeleton_wave_speed); so ξ_max = β_K ω_s,max²/(2 ω_max) =
/// (β_K/dt_c)(dt_c/dt_c,s)². Dry, dt_c,s = dt_c and this is the one above, bit for bit.
/// (A saturated element's skeleton alone is 6–40 times slower than the undrained mixture,
/// and the step grows as much where β_K bound it.)
double damped_time_step(double critical_step, double courant, double rayleigh_stiffness,
                        double skeleton_step);

}  // namespace slide::fem
