// The checkpoint schema: the only way the three programs exchange state.
//
// One module writes and reads it, one dataset per field. Every read validates: the file
// attributes (schema, schema_version, kind), every required dataset's presence, type
// and shape, finite values, and index ranges. A failure is an Error naming the file,
// the dataset and what was expected. Every write goes to a temporary file in the target
// folder and is renamed into place, so an existing checkpoint is never left truncated.
// The full schema, dataset by dataset, is documented in common/io/checkpoint-schema.md.
#pragma once

#include <cstdint>
#include <filesystem>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "common/base/ranks.hpp"
#include "common/base/types.hpp"
#include "common/geometry/mesh.hpp"
#include "common/physics/constitutive.hpp"
#include "common/physics/fe_fields.hpp"
#include "common/physics/ground_motion.hpp"
#include "common/physics/material.hpp"
#include "common/physics/particles.hpp"

namespace slide {

inline constexpr const char* checkpoint_schema_name = "fem-mpm-checkpoint";
/// Bumped whenever a name or meaning of the schema changes (docs/contract.md).
inline constexpr std::int64_t checkpoint_schema_version = 2;
/// The oldest version the readers still read (checkpoint-schema.md, Versioning).
inline constexpr std::int64_t oldest_checkpoint_schema_version = 1;

enum class CheckpointKind { fem, particles, mpm };
std::string_view to_string(CheckpointKind kind);

/// File attributes common to every kind.
struct CheckpointHeader {
  CheckpointKind kind = CheckpointKind::fem;
  std::int64_t schema_version = checkpoint_schema_version;
  std::string producer;   ///< program and version, e.g. "fem-solve (slide 0.1.0)"
  double time = 0.0;      ///< s, on the clock of docs/method.md §2
  std::int64_t step = 0;  ///< time steps behind the state (checkpoint-schema.md)
  std::string case_name;
  double pe0 = 0.0;  ///< PE_0, J/m: potential energy of the model at t = 0
};

/// Free-form solver settings a restart needs (attributes of the /solver group), e.g.
/// "stage" = "failure", "time_step" = 1.2e-3.
using SettingValue = std::variant<std::int64_t, double, std::string>;
using SolverSettings = std::map<std::string, SettingValue>;

/// The base motion of a shaken run (optional group /motion, docs/method.md §8): the
/// processed samples of common/physics/ground_motion.hpp and how the base took them, so
/// that a later stage (or a restart) continues the same earthquake.
struct CheckpointMotion {
  double start_time = 0.0;  ///< s on the run's clock of the first sample
  double step = 0.0;        ///< s between samples
  std::vector<Vec2> acceleration, velocity, displacement;  ///< n_samples each
  std::string base;                                        ///< "rigid" or "compliant"
  std::string input;  ///< "incident" or "outcrop" (what the samples are at a compliant base)
  /// Where the FE model's base was (the mean displacement of its base nodes) at
  /// `base_time`: the motion's own displacement for a rigid base; for a compliant one it
  /// includes the drift of the whole model on its dashpots. The MPM grid starts there.
  Vec2 base_displacement = Vec2::Zero();
  double base_time = 0.0;
  /// s on the run's clock where the record ends: after the last sample when the samples
  /// were kept only up to the end of the case's runs (NaN: at the last sample).
  double record_end_time = std::numeric_limits<double>::quiet_NaN();
};

/// The motion the MPM grid's base follows: the samples, or, after a compliant base
/// driven by the incident wave, twice them (the outcrop motion; the MPM base is rigid).
GroundMotion grid_motion(const CheckpointMotion& motion);
/// The base's displacement at `time` as the MPM grid follows it: base_displacement plus
/// the grid motion's displacement since base_time. Positions measured from the base
/// (the runout) are positions minus this.
Vec2 base_position(const CheckpointMotion& motion, const GroundMotion& grid, double time);

/// The samples of `motion` as a checkpoint records them.
CheckpointMotion checkpoint_motion(const GroundMotion& motion, std::string base, std::string input);
/// The motion a checkpoint recorded.
GroundMotion ground_motion(const CheckpointMotion& motion);

/// Kind "fem": the FE model at one time: its state (FeFields, common/physics/fe_fields.hpp)
/// and what is derived from the mesh and the state for the transfer and the tools.
struct FemCheckpoint : FeFields {
  CheckpointHeader header;
  Mesh mesh;  ///< reference coordinates, connectivity, material ids, boundary node sets
  /// Condition applied to each node set in the stage that wrote the file
  /// (same order as mesh.node_sets), and the base friction coefficient μ.
  std::vector<BoundaryCondition> boundary_conditions;
  double friction_coefficient = 0.0;

  std::vector<Vec2> coordinates;  ///< per node: current x = X + u

  // Elements (n_elements each).
  std::vector<double> jacobian_ratio;  ///< |J_t|/|J_0| at the element centre
  /// Minimum scaled corner Jacobian (scaled_jacobian in common/geometry/element.hpp); empty when
  /// the file predates it (the dataset is optional).
  std::vector<double> scaled_jacobian;
  std::vector<double> volume_reference;  ///< V_0^e
  std::vector<double> volume;            ///< V_t^e

  // Gauss points (n_gp each), element by element in the order of the element's rule.
  std::vector<Index> gauss_element;
  std::vector<Vec2> gauss_local_coordinates;
  std::vector<Vec2> gauss_coordinates;  ///< current x
  std::vector<double> gauss_weight;     ///< reference quadrature weight
  std::vector<double> eps_q;            ///< εq of `strain`

  MaterialTable materials;
  SolverSettings solver;
  std::optional<CheckpointMotion> motion;
};

/// Extra information a particle file (kind "particles") carries about its transfer.
struct TransferSettings {
  double transfer_time = 0.0;
  std::string particles_per_element;  ///< e.g. "4x4", or "16" for triangles
  std::string stress_interpolation;   ///< "rbf", "rbf-local" or "element"
  std::string rbf_polynomial;         ///< "none" or "linear"
  double rbf_shape = 0.0;             ///< multiquadric shape parameter c, m (0: unused)
  std::int64_t rbf_neighbours = 0;    ///< k of rbf-local (0: unused)
};

/// Kinds "particles" (fem2mpm output) and "mpm" (mpm-solve checkpoints).
struct ParticleCheckpoint {
  CheckpointHeader header;
  Particles particles;
  MaterialTable materials;
  TransferSettings transfer;  ///< kind "particles"; also kept in "mpm" files when known
  SolverSettings solver;      ///< kind "mpm": grid and solver settings for a restart
  std::optional<CheckpointMotion> motion;  ///< the base motion the run continues
  std::size_t file_rows = 0;               ///< particle rows in the file
  std::size_t first_row = 0;               ///< the file row of particles[0] (read in parts: not 0)
};

/// About the bytes of an FE checkpoint of `state` on `mesh`: the state's arrays, the
/// reference and current coordinates, the connectivity and material ids (its other
/// datasets, per element and Gauss point, are left out: a lower estimate). What the
/// writer checks against the free space and fem-solve's run estimate counts per file.
double fem_checkpoint_bytes(const FeFields& state, const Mesh& mesh);

/// Writes atomically (temporary file + rename). Throws Error on any failure; the target
/// is then untouched.
void write_checkpoint(const std::filesystem::path& path, const FemCheckpoint& checkpoint);
void write_checkpoint(const std::filesystem::path& path, const ParticleCheckpoint& checkpoint);
/// A particle checkpoint that every rank writes together (collective; parallel HDF5,
/// docs/parallel.md): each rank's `checkpoint` holds its own particles, the last `frozen`
/// of them frozen, and the same header, materials and settings. The file is a serial
/// one in every respect: its rows are every rank's active particles in rank order, then
/// every rank's frozen ones, so that a serial run reads it as its own. On one rank the
/// same as write_checkpoint.
void write_checkpoint_on_ranks(const std::filesystem::path& path,
                               const ParticleCheckpoint& checkpoint, std::size_t frozen,
                               const Ranks& ranks);

/// Reads and validates a kind "fem" file.
FemCheckpoint read_fem_checkpoint(const std::filesystem::path& path);
/// Reads and validates a kind "particles" or "mpm" file, or of it only the particle rows
/// of `part` (Part::rows; their ids are then checked unique among themselves only).
ParticleCheckpoint read_particle_checkpoint(const std::filesystem::path& path,
                                            const Part& part = {});
/// Everything of a kind "particles" or "mpm" file but its particle rows (file_rows is
/// set, the particles are empty): what a run decides before it reads them.
ParticleCheckpoint read_particle_checkpoint_settings(const std::filesystem::path& path);
/// Reads and validates only the file attributes.
CheckpointHeader read_checkpoint_header(const std::filesystem::path& path);

}  // namespace slide
