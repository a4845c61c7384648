// The MPM kernels: free functions over ranges of the particle arrays (common/physics/particles.hpp)
// and the grid's nodal arrays. The step loop (mpm_solver.cpp) calls them in order.
//
// Parallel scatter without atomics or locks. The active particles (sorted by cell,
// x-major) are split into a fixed number of contiguous blocks; the number depends only
// on the particle count, never on the thread count. Each block scatters into its own
// private window of node columns (the band its particles touch) and the windows are then
// summed into the grid node by node, in block order. Every floating-point sum therefore
// happens in the same order whatever the number of threads: results are bit-identical
// from run to run, on 1 thread or many, and a restart (which keeps the particle order)
// reproduces a continuous run exactly.
//
// Time integration is the explicit central difference on the grid: velocities live at
// half steps. With Δt_n the step and Δt_v = ½(Δt_{n−1} + Δt_n) the velocity step
// (Δt_{−1} = 0 at a fresh start, which is the initial half kick),
//   v_i^{n+½} = v_i^{n−½} + Δt_v F_i/m_i,   x_p^{n+1} = x_p^n + Δt_n Σ_i N_ip v_i^{n+½}.
// A body under constant acceleration then follows x = ½ g t² exactly.
//
// Velocity transfer (mpm.velocity_transfer). "flip-pic": the particle velocity is
// updated by the nodal velocity change (FLIP), blended with the nodal velocity itself
// (PIC) by α = pic_fraction; P2G maps m_p v_p. FLIP keeps the energy but lets the grid's
// null-space noise build up on the particles; PIC removes it by averaging every
// particle's velocity over its cell, which dissipates any motion that varies within a
// cell (α = 0.01 costs 10 % of column-short's runout).
// "apic" (Jiang et al. 2015, "The affine particle-in-cell method"): each particle also
// carries an affine velocity matrix C_p (Particles::affine_velocity, 1/s), so that what
// it hands to the grid is the affine field v_p + C_p (x − x_p):
//   P2G   p_i = Σ_p N_ip m_p (v_p + C_p (x_i − x_p)),
//   G2P   v_p = Σ_i N_ip v_i^L,   C_p = Σ_i v_i^L (N_ip D_p⁻¹ (x_i − x_p))ᵀ,
//         x_p += Δt Σ_i N_ip v_i^L,
// with D_p = Σ_i N_ip (x_i − x_p)(x_i − x_p)ᵀ at the particle's position where it
// gathers. The particle takes what the grid can represent of the nodal field (its value
// and its first moment) instead of PIC's value alone: any linear velocity field
// (translation, rigid rotation, uniform shear) passes grid → particles → grid unchanged,
// and a transfer conserves the angular momentum Σ_p m_p (x_p × v_p + (C_p D_p)_yx −
// (C_p D_p)_xy) exactly. There is no FLIP increment, hence no null-space noise and no PIC
// share; what it dissipates is only the motion the grid cannot represent (sub-cell
// variations beyond linear). MUSL does the same in its velocity pass (v_p and C_p from
// v^L, and the re-projected momenta include N_ip m_p C_p (x_i − x_p)); the stress update
// keeps the velocity gradient L_p = Σ_i v_i ⊗ ∇N_ip of the nodal velocities (MUSL: the
// re-projected ones).
//
// D_p for linear and uGIMP shape functions (shape_functions.hpp): diagonal, from the
// particle's own weights, D = h² Σ_k S_k (k − ξ)² per axis; not constant (uGIMP at 4 × 4
// particles per cell: between h²/16 on a node line and h²/4 at a cell centre; linear:
// h² f(1 − f), zero on a node line). The particle carries C_p itself across its move
// (the MLS-MPM form, Hu et al. 2018), so P2G needs no D_p at all: N_ip (x_i − x_p) is the
// weights' first moment. Carrying B_p = C_p D_p instead, as Jiang et al. do with their
// constant D = h²/4 (quadratic B-splines), would hand the next P2G C_p D_p(x^n)
// D_p(x^{n+1})⁻¹: an affine flow turned into a spurious stretching by up to a factor 4 for
// uGIMP and without bound for linear hats near a node line (tests/mpm/test_apic.cpp: a
// ballistic shear flow stays exact on moving particles this way and fails the other
// way). The price: angular momentum, exact in each transfer, changes across the move by
// the change of each particle's spin m_p ε:(C_p D_p), at most m_p |C_p| h²/4. For linear
// hats N_ip D_p⁻¹ (x_i − x_p) = ∇N_ip, so C_p is the nodal velocity gradient and the
// gather never needs D_p⁻¹. C_p is gathered in the final pass (USL) or in MUSL's
// velocity pass.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "common/physics/algorithms.hpp"
#include "common/physics/constitutive.hpp"
#include "common/physics/particles.hpp"
#include "mpm/grid.hpp"

namespace slide::mpm {

/// The fixed partition of the active particles [0, n) into blocks and each block's
/// scatter windows.
struct ParticleBlocks {
  std::vector<std::size_t> offsets;           ///< block b is [offsets[b], offsets[b+1])
  std::vector<int> column_begin, column_end;  ///< node-column band block b touches
  std::vector<std::vector<NodeSums>> sums_window;
  std::vector<std::vector<Vec2>> momentum_window;  ///< MUSL re-projection
  std::vector<std::vector<CellSums>> cell_window;  ///< volumetric smoothing
  // Volumetric smoothing: what the final pass keeps of each active particle between its
  // two halves (contiguous, indexed like the particles).
  std::vector<Vec4> velocity_gradient;  ///< L_p
  std::vector<Vec2> step_displacement;  ///< Δt Σ N_ip v_i^L
  std::vector<double> kinetic_energy;   ///< partial sums of ½ m v²
  /// Each active particle's shape weights of the step (values, derivatives, APIC's
  /// inputs), computed once by P2G and read by the MUSL velocity pass and the final
  /// pass: the particles move only at the end of the step. Raw storage of the kernels'
  /// weight type for the shape function (kernels.cpp), indexed like the particles.
  std::vector<std::byte> shape_weights;
  bool parallel = false;  ///< worth running the kernels on several threads

  /// Splits n active particles into blocks; their number depends on n only.
  void partition(std::size_t active_count);
  std::size_t count() const { return offsets.empty() ? 0 : offsets.size() - 1; }
  std::size_t bytes() const;
};

/// Lengths of one step (see the header comment).
struct StepLengths {
  double dt = 0.0;           ///< Δt_n: positions and strains
  double dt_velocity = 0.0;  ///< Δt_v = ½(Δt_{n−1} + Δt_n): velocities
};

/// What locating the particles found.
struct LocateResult {
  std::int64_t non_finite = -1;      ///< first particle with a NaN/Inf position, or −1
  std::vector<std::size_t> outside;  ///< active particles whose centre left the grid
};

/// Checks the active particles [0, n_active) against the grid and computes each
/// block's node-column band for the shape function.
LocateResult locate_particles(const Particles& particles, std::size_t active_count,
                              const GridGeometry& grid, ShapeFunction shape,
                              ParticleBlocks& blocks);

/// APIC's D_p = Σ_i N_ip (x_i − x_p)(x_i − x_p)ᵀ of a particle at `position` (diagonal
/// for these tensor-product weights): (D_xx, D_yy), m².
Vec2 affine_inertia(const GridGeometry& grid, ShapeFunction shape, const Vec2& position,
                    const Vec2& size);

/// Water standing outside the body up to `level` (docs/method.md §10): its hydrostatic
/// pressure p_w = γ_w (level − y) acts on the body's submerged surface. Gravity is along
/// −y. Inactive (γ_w = 0) by default.
struct Reservoir {
  double level = 0.0;                                       ///< m
  double unit_weight = 0.0;                                 ///< γ_w = ρ_w g, N/m³
  double x_min = -std::numeric_limits<double>::infinity();  ///< the x range it covers, m
  double x_max = std::numeric_limits<double>::infinity();
  bool active() const { return unit_weight > 0.0; }
  /// p_w at x (0 above the level and outside the range).
  double pressure(const Vec2& x) const {
    return x.y() < level && x.x() >= x_min && x.x() <= x_max ? unit_weight * (level - x.y()) : 0.0;
  }
};

/// Pass 1, particles → grid, into each block's window: m_i = Σ N_ip m_p,
/// p_i = Σ N_ip m_p v_p (APIC: Σ N_ip m_p (v_p + C_p (x_i − x_p))),
/// f_i = Σ (N_ip m_p g − V_p (σ′_p − (p_p − p_w) I)·∇N_ip + N_ip V_p γ_w ŷ [submerged])
/// (plane strain: σxx, σyy, σxy take part). σ′ − p I is the total stress of a particle
/// with pore pressure p (0 for dry soil); the reservoir's terms are its traction −p_w n on
/// the submerged surface, written over the volume by the divergence theorem,
/// −∫ (p_w ∇N_i + N_i ∇p_w) dV: inside a submerged body they cancel node by node, at its
/// surface they are the water's load, and their sum is Archimedes' buoyancy.
/// Also keeps each particle's shape weights in ParticleBlocks::shape_weights, which the
/// step's later particle passes (remap_momenta, grid_to_particles) read: they must follow
/// it in the same step, with the particles where it found them.
void particles_to_grid(const Particles& particles, const GridGeometry& grid, ShapeFunction shape,
                       VelocityTransfer transfer, const Vec2& gravity, ParticleBlocks& blocks,
                       GridState& state, const Reservoir& reservoir = {});

/// The grid update in its two halves, for a run on several ranks (mpm/domain.hpp), which
/// completes the shared nodes' sums between them: the blocks' windows summed into the
/// nodes in block order; then the nodal update (below) of the summed nodes, whose
/// constraint power counts the nodes of GridState's own columns only.
void sum_node_windows(const GridGeometry& grid, const ParticleBlocks& blocks, GridState& state);
double update_nodes(const GridGeometry& grid, const GridBoundaries& boundaries,
                    const NodalDamping& damping, double dt_velocity, double mass_floor,
                    GridState& state);

/// The grid update, column by column: the blocks' windows summed in block order, then
/// the nodal update (common/physics/nodal_update.hpp: damping, then the constraints of the grid
/// edges): v_i = p_i/m_i, v_i^L and a_i = (v_i^L − v_i)/Δt_v.
/// Returns the power of the constraints when the boundaries are moving (Σ m (v − v*)·v
/// / dt_v over the constrained nodes, W/m; the solver multiplies it by the step), else 0.
double update_grid(const GridGeometry& grid, const GridBoundaries& boundaries,
                   const NodalDamping& damping, double dt_velocity, double mass_floor,
                   const ParticleBlocks& blocks, GridState& state);

/// MUSL's pass 2 in its two halves (see sum_node_windows): the particle velocities and
/// the re-projected momenta summed into GridState::remapped_velocity; then those momenta
/// divided by the nodal masses, with the kinematic constraints.
void remap_momenta(Particles& particles, const GridGeometry& grid, ShapeFunction shape,
                   VelocityTransfer transfer, const StepLengths& step, double pic_fraction,
                   ParticleBlocks& blocks, GridState& state);
void finish_remapped_velocities(const GridGeometry& grid, const GridBoundaries& boundaries,
                                double mass_floor, GridState& state);

/// MUSL, pass 2: the particle velocities from the grid (FLIP with a PIC share α),
///   v_p ← (1 − α)(v_p + Δt_v Σ N_ip a_i) + α Σ N_ip v_i^L,
/// (APIC: v_p = Σ N_ip v_i^L and C_p, α unused)
/// and the updated momenta mapped back to the grid (APIC: with the affine part
/// N_ip m_p C_p (x_i − x_p)); then the re-projected nodal velocities Σ N m v / m_i with
/// the edges' kinematic constraints (no friction: it acted on the forces already).
void update_particle_velocities_and_remap(Particles& particles, const GridGeometry& grid,
                                          const GridBoundaries& boundaries, ShapeFunction shape,
                                          VelocityTransfer transfer, const StepLengths& step,
                                          double pic_fraction, double mass_floor,
                                          ParticleBlocks& blocks, GridState& state);

/// Final pass, grid → particles, block by block: position and displacement
/// x_p += Δt Σ N_ip v_i^L, the velocity gradient L_p = Σ v_i ⊗ ∇N_ip (v_i: re-projected
/// in MUSL, v_i^L in USL; USL also updates the velocities here, as above, and APIC's
/// C_p = Σ v_i^L (N_ip D_p⁻¹ (x_i − x_p))ᵀ), and at once,
/// particle by particle, the stress update: strain increment Δε = Δt sym(L), spin
/// ω = ½ Δt (∂vx/∂y − ∂vy/∂x), Jaumann rotation, the constitutive update (one model per
/// material id), accumulated strain and its εq, and the volume from the particle's own
/// deformation-gradient increment, V_{n+1} = det(I + Δt L_p) V_n. Then, while the block
/// is in cache, its location on the grid for the next step (returned). Accumulates the
/// kinetic energy per block.
///
/// Volumetric smoothing "cell" (mpm/README.md, "Volumetric smoothing") splits the pass in
/// two around the volume-weighted averages over each cell's particles of the volumetric
/// rate tr L_p and the mean stress p_p (at the step's start), summed in block order. The
/// second half gives each particle its cell's mean stress, keeping its deviator, then
/// updates stress and volume with L_p + ½ (tr L̄ − tr L_p) I: deviatoric rate and spin
/// are the particle's own, pressure and volumetric rate the cell's (a B-bar type,
/// constant-pressure-per-cell treatment). The particles move (and are located) in the
/// second half, so that both halves see the cells of the step's start.
LocateResult grid_to_particles(Particles& particles, const GridGeometry& grid, ShapeFunction shape,
                               UpdateScheme scheme, VelocityTransfer transfer,
                               const StepLengths& step, double pic_fraction,
                               VolumetricSmoothing smoothing,
                               std::span<const ConstitutiveModel> models, ParticleBlocks& blocks,
                               GridState& state);

/// The model of particle p in a table of 2 × `materials` models: its material's MPM
/// model, or in the second half its material's liquefied state when the transfer marked
/// the particle liquefied (docs/method.md §10; MpmSolver builds the table).
inline std::size_t particle_model(const Particles& particles, std::size_t p,
                                  std::size_t materials) {
  const auto material = static_cast<std::size_t>(particles.material_id[p]);
  if (particles.liquefied.empty() || particles.liquefied[p] == 0) return material;
  return material + materials;
}

/// Runs `update` (a callable on a stress) on particle p's stress as its model sees it,
/// and returns what it returns: a liquefied particle's residual strength works on the
/// total stress σ′ − p I (Tresca does not see the shift; its tension cut-off is the
/// mixture's: the water holds the grains apart until the total stress is tensile), the
/// other models on σ′.
template <class Update>
auto on_model_stress(const ConstitutiveModel& model, Particles& particles, std::size_t p,
                     Update&& update) {
  Vec4& stress = particles.stress[p];
  if (model.model() != MaterialModel::residual_strength) return update(stress);
  const double pressure = particles.pore_pressure[p];
  for (int i = 0; i < 3; ++i) stress[i] -= pressure;
  const auto result = update(stress);
  for (int i = 0; i < 3; ++i) stress[i] += pressure;
  return result;
}

/// Whether particle p's pores hold water, so that its pore pressure evolves undrained
/// ([mpm.pore_water] pore_pressure = "undrained"): it was below the water table at the
/// transfer, its steady pore pressure p − Δp being positive (without Δp, p itself). Above
/// the table the pores hold air, which takes no load: a particle of a saturable material
/// there keeps p = 0 however it is compressed. p − Δp stays as transferred (both change
/// by the same ṗ), so a particle that cavitates (p = 0) loads its water again.
inline bool holds_water(const Particles& particles, std::size_t p) {
  const double steady = particles.excess_pore_pressure.empty()
                            ? particles.pore_pressure[p]
                            : particles.pore_pressure[p] - particles.excess_pore_pressure[p];
  return steady > 0.0;
}

/// Stable counting sort of the particles by cell (x-major); particles from
/// `active_count` on (frozen ones) keep their order at the end. In place: the only
/// per-particle memory it takes is the 4-byte permutation.
void sort_particles_by_cell(Particles& particles, std::size_t active_count,
                            const GridGeometry& grid);

/// Copies every field of particle `from` onto particle `to` (`from` is left as it was).
void move_particle(Particles& particles, std::size_t to, std::size_t from);

/// Moves the particles listed in `indices` (sorted, all < active_count) behind the active
/// ones (freeze) or deletes them (remove), keeping the order of the others. Returns the
/// new active count.
std::size_t retire_particles(Particles& particles, std::size_t active_count,
                             std::span<const std::size_t> indices, ParticleExit mode);

}  // namespace slide::mpm
