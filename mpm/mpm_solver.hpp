// The explicit material point method (docs/method.md §5): one body of material points on a
// background grid, stepped in time. The solver owns the particles and the per-step
// scratch; it knows nothing about files (mpm_run.hpp drives it and writes the output).
//
// One step, Δt (positions, strains) and Δt_v = ½(Δt_prev + Δt) (velocities):
//   1. locate       particles on the grid; those that left are frozen or removed
//   2. sort         by cell every `sort_interval` steps (locality of the grid access)
//   3. P2G          m_i, p_i and f_i = Σ N m g − Σ V σ·∇N
//   4. grid         v_i^L = v_i + Δt_v F_i/m_i with damping and the edge constraints
//   5. G2P          (MUSL: velocities, then momenta re-projected to the grid)
//   6. G2P          positions x += Δt Σ N v^L, velocity gradients L_p (APIC: the affine
//                   velocities B_p), and particle by
//   7. stresses     particle: Jaumann rotation, constitutive update, strain, εq, volume;
//                   block by block (in cache) the particles' location for the next step
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "common/base/error.hpp"
#include "common/io/checkpoint.hpp"
#include "common/physics/constitutive.hpp"
#include "common/physics/ground_motion.hpp"
#include "common/physics/material.hpp"
#include "common/physics/particles.hpp"
#include "common/settings/mpm_spec.hpp"
#include "mpm/domain.hpp"
#include "mpm/grid.hpp"
#include "mpm/kernels.hpp"

namespace slide::mpm {

/// A run that went unstable: NaN/Inf, speeds beyond the physical bound, energy growth.
class InstabilityError : public Error {
 public:
  using Error::Error;
};

/// Everything the solver needs besides materials and particles.
struct MpmSettings {
  GridGeometry grid;
  GridBoundaries boundaries;
  ShapeFunction shape_function = ShapeFunction::gimp;
  UpdateScheme update_scheme = UpdateScheme::musl;
  VelocityTransfer velocity_transfer = VelocityTransfer::flip_pic;
  double pic_fraction = 0.0;  ///< flip-pic only
  VolumetricSmoothing volumetric_smoothing = VolumetricSmoothing::none;
  NodalDamping damping;
  Vec2 gravity = gravity_vector();
  Reservoir reservoir;  ///< water outside the body (inactive: none)
  /// K_f of the pore water when saturated particles evolve undrained ([mpm.pore_water]
  /// pore_pressure = "undrained"), Pa; 0: their pore pressure stays as transferred.
  double pore_fluid_bulk_modulus = 0.0;
  ParticleExit particle_exit = ParticleExit::freeze;
  /// Steps between two sorts by cell. Chosen by measurement (bench_mpm on the collapsing
  /// column-short, 1 m cells at the Courant step): every 10 steps was fastest; every 2–5
  /// steps spends more on sorting than it gains, every 20–40 steps lets the particles
  /// drift across cells, which widens the scatter windows and scatters the grid access.
  int sort_interval = 10;

  static MpmSettings from(const MpmSpec& spec);
};

/// The solver's counters: everything a restart needs besides particles and settings.
struct SolverClock {
  double time = 0.0;
  std::int64_t step = 0;
  double previous_dt = 0.0;  ///< Δt_{n−1}; 0 before the first step (half kick)
  std::int64_t steps_since_sort = 0;
  bool sorted_once = false;  ///< false: sort before the first step
  std::size_t frozen = 0;    ///< the last `frozen` particles are frozen
  /// Work the moving base's constraints did on the body since the start of the run
  /// (docs/method.md §8), J/m: the energy guard measures the total energy against it.
  double boundary_work = 0.0;
};

/// What one step did that the driver reports.
struct StepReport {
  std::size_t exited = 0;  ///< particles that left the grid in this step (all ranks)
};

/// Energies of the particle body, J/m.
struct Energies {
  double kinetic = 0.0;    ///< Σ ½ m v²
  double potential = 0.0;  ///< −Σ m g·x (g·x = −9.81 y for the default gravity)
  double elastic = 0.0;    ///< Σ V ½ σ:C⁻¹:σ (stored elastic energy)
  double total() const { return kinetic + potential + elastic; }
};

class MpmSolver {
 public:
  /// Takes the particles (validated: see validate_particles) and sorts them by cell on
  /// the first step unless `clock.sorted_once`. APIC particles without an affine velocity
  /// (a particle file, pure MPM) start with B_p = 0; a FLIP/PIC run drops any it finds.
  MpmSolver(MpmSettings settings, MaterialTable materials, Particles particles,
            SolverClock clock = {});

  /// Runs on several ranks from now on (docs/parallel.md, mpm/domain.hpp): the grid is cut
  /// into slabs balanced on the particles, and every particle goes to the rank of its
  /// slab. Until this call each rank holds a disjoint part of the particles, in the order
  /// of the whole set (keep_part, or a particle file read in parts), with the part's
  /// frozen particles last. From then on step, courant_time_step, energies and
  /// last_kinetic_energy are collective and give the values of the whole body; the
  /// particles, active_count and max_speeds are this rank's. On one rank it does nothing.
  void distribute(const Ranks& ranks, const Decomposition& decomposition = {});
  const Subdomain* subdomain() const { return subdomain_ ? &*subdomain_ : nullptr; }
  /// The ranks the solver runs on (one, until distribute).
  const Ranks& ranks() const { return subdomain_ ? subdomain_->ranks() : Ranks::single(); }

  /// One explicit step of length dt > 0 (see the header comment).
  StepReport step(double dt);
  /// The base motion the grid follows from now on (docs/method.md §8): the grid translates
  /// with the base, its origin at the resting origin + u_g(t) at the start of each step;
  /// over the step t → t + dt its edges move at (u_g(t + dt) − u_g(t))/dt and every
  /// constraint acts on the velocity relative to that. Particles stay absolute.
  /// `record` places the base at the start (CheckpointMotion::base_displacement).
  void set_base_motion(GroundMotion motion, const CheckpointMotion& record);
  /// The base's displacement at `time` (the grid's shift from its resting origin; zero
  /// without a motion): positions measured from the base are positions minus this.
  Vec2 base_shift(double time) const { return grid_origin_at(time) - base_.resting_origin; }
  /// Where the grid's origin is at `time` (the settings' origin without a motion).
  Vec2 grid_origin_at(double time) const;
  const std::optional<GroundMotion>& base_motion() const { return base_.motion; }

  /// The models the stress update uses: the materials' own (default) or linear elastic
  /// with the same constants (gravity stage of pure MPM).
  void use_elastic_models(bool elastic);
  /// Returns every inadmissible stress to the yield surface once (an update with a zero
  /// strain increment): the switch from an elastic initial state to the plastic model.
  /// Returns how many particles were outside the yield surface.
  std::size_t return_to_yield_surface();

  /// Pure MPM's elastic gravity stage (docs/method.md §5): `duration` s of steps of at most
  /// `dt` with linear-elastic models and local damping α = `local_damping`; then the
  /// velocities, affine velocities, displacements, strains and states are reset and the
  /// clock starts at t = 0: the equilibrium the plastic run starts from. The settings
  /// and models are the run's own again afterwards.
  struct Settling {
    std::int64_t steps = 0;
    double kinetic_energy = 0.0;  ///< at the stage's end, before the reset, J/m
  };
  Settling settle_under_gravity(double duration, double local_damping, double dt);
  /// The step just taken ends at `time` instead (within a rounding of the clock's own):
  /// a schedule's time, so that a run and its restart stop at exactly the same times.
  void land_on(double time) { clock_.time = time; }

  const MpmSettings& settings() const { return settings_; }
  const MaterialTable& materials() const { return materials_; }
  /// The particles, read-only: a run sets them up before the solver takes them, and the
  /// solver's own setup steps (settle_under_gravity) reset what they change.
  const Particles& particles() const { return particles_; }
  const SolverClock& clock() const { return clock_; }
  std::size_t active_count() const { return particles_.count() - clock_.frozen; }

  /// Kinetic energy after the last step (block partial sums, no extra pass).
  double last_kinetic_energy() const { return last_kinetic_energy_; }
  Energies energies() const;
  /// The largest particle speed and the largest speed of a grid node carrying at least
  /// `node_mass_share` of the smallest particle mass (lighter nodes move no particle
  /// noticeably: their weight in any interpolation is that small).
  struct Speeds {
    double particle = 0.0;
    std::size_t particle_index = 0;
    double node = 0.0;
    Vec2 node_position = Vec2::Zero();
  };
  Speeds max_speeds(double node_mass_share = 0.1) const;
  /// Grid node mass Σ_i m_i of the last step (tests: partition of unity).
  double grid_mass() const;

  /// Stable Courant step C h / max_p c_p over the active particles, with c_p² = M V_p / m_p
  /// at each particle's current density (the materials' own speeds when none is active).
  /// Throws InstabilityError for a particle whose volume is not finite and positive or
  /// exceeds max_expansion times its mass over its material's density.
  double courant_time_step(double courant) const;
  static constexpr double max_expansion = 1e4;

  /// Moves the particle arrays out of the solver and back (no copy), for a writer that
  /// takes a Particles value (the checkpoint); the solver must not step in between, and
  /// the same particles must come back.
  Particles lend_particles() { return std::move(particles_); }
  void return_particles(Particles particles) { particles_ = std::move(particles); }

  /// Memory held in the particle arrays, the sort's temporary peak (the step itself
  /// allocates nothing per particle) and the grid with its scatter windows.
  struct Memory {
    std::size_t particle_arrays = 0, sort_peak = 0, grid = 0;
    std::size_t total() const { return particle_arrays + sort_peak + grid; }
  };
  Memory memory() const;

 private:
  void locate();
  void sort();
  /// APIC: one affine velocity per particle (zeros for those that came without).
  void size_affine_velocity();
  /// courant_time_step's test of particle p, whose c_p² is `wave_speed_squared`.
  void check_volume(std::size_t p, double wave_speed_squared) const;

  MpmSettings settings_;
  MaterialTable materials_;
  std::vector<ConstitutiveModel> models_;
  Particles particles_;
  SolverClock clock_;
  GridState grid_state_;
  ParticleBlocks blocks_;
  LocateResult pending_;  ///< where the last step's final pass found the particles
  bool located_ = false;  ///< pending_ matches the particles
  double mass_floor_ = 0.0;
  double last_kinetic_energy_ = 0.0;
  std::size_t exited_this_step_ = 0;
  /// The base motion the grid follows (none: a static base).
  struct MovingBase {
    std::optional<GroundMotion> motion;
    Vec2 resting_origin = Vec2::Zero();  ///< the grid's origin with the base at rest
    CheckpointMotion record;
  };
  MovingBase base_;

  void follow_base(double dt);
  /// On several ranks: particles to their owners (and re-cut slabs at sorting time).
  void exchange_particles(bool sorting);
  void set_own_columns();
  /// How this run packs a particle for another rank (surfaces, APIC's affine velocity).
  PackedLayout packed_layout() const;

  std::optional<Subdomain> subdomain_;
};

/// Checks particles before a run; throws Error naming `source` and the first bad
/// particle (index and id): non-finite fields, mass or volume ≤ 0, size ≤ 0 for uGIMP,
/// an unknown material id, a particle outside the grid. Frozen particles (the last
/// `frozen`) may lie outside.
void validate_particles(const Particles& particles, const MpmSettings& settings,
                        std::size_t material_count, const std::string& source,
                        std::size_t frozen = 0);

}  // namespace slide::mpm
