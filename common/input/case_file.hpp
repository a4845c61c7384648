// The case file: one `cases/<name>/case.toml` drives all three programs (geometry,
// materials, FE stages, transfer, MPM, metrics). The reader is strict: an unknown key, a
// missing required key, a wrong type or an impossible value is an Error of the form
//   case.toml:12: fem.end_time = -1 is not admissible (expected > 0 s)
// naming the file, the line and the dotted key. The file format is documented key by
// key in common/input/case-file.md; every case in cases/ is a commented example.
#pragma once

#include <array>
#include <cstddef>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "common/base/types.hpp"
#include "common/geometry/element.hpp"
#include "common/geometry/mesh.hpp"
#include "common/physics/algorithms.hpp"
#include "common/physics/material.hpp"

namespace slide {

// ----------------------------------------------------------------------------- mesh

enum class MeshGenerator {
  profile,   ///< columns under a surface polyline over the base y = 0 (mapped mesh)
  blocks,    ///< multi-block transfinite (mapped) quads with explicit corner points
  gmsh,      ///< a Gmsh .msh file (4.1 or 2.2 ASCII)
  opensees,  ///< an OpenSees model printed with `print -JSON` (opensees_reader.hpp)
};

/// One mapped block: four corners counter-clockwise, cells along the first side (0→1)
/// and along the second side (1→2). Blocks that share an edge share its nodes.
struct MeshBlock {
  std::array<Vec2, 4> corners;
  int cells_u = 1;
  int cells_v = 1;
  std::string material;
};

struct MeshSpec {
  MeshGenerator generator = MeshGenerator::profile;
  ElementType element_type = ElementType::quad4_1gp;
  // profile
  double element_size = 1.0;  ///< target element size h, m
  std::vector<Vec2> surface;  ///< surface points, x increasing from the wall x = 0
  std::string material;       ///< material of the whole profile mesh
  // blocks
  std::vector<MeshBlock> blocks;
  // gmsh (relative paths are relative to the case file's folder)
  std::filesystem::path gmsh_file;
  // opensees: the JSON model, its nDMaterial tags → case materials, element classes to skip
  std::filesystem::path opensees_file;
  std::map<std::string, std::string> opensees_materials;
  std::vector<std::string> ignore_elements;

  /// The mesh file the case reads (Gmsh or OpenSees), empty for generated meshes.
  std::filesystem::path file() const {
    return generator == MeshGenerator::gmsh       ? gmsh_file
           : generator == MeshGenerator::opensees ? opensees_file
                                                  : std::filesystem::path();
  }
};

// ----------------------------------------------------------------------------- OpenSees import

/// [opensees]: the recorder files opensees2fem reads (tools/interop/README.md); paths
/// absolute (given relative to the case file's folder). Empty paths: not recorded.
struct OpenSeesImportSpec {
  /// The recorder time of the reference state (fem-solve's u = 0, the end of the gravity
  /// stage): displacement and strain are measured from the first row at this time.
  std::optional<double> reference_time;
  /// The recorder time of the start of the failure stage (t = 0 of the checkpoints); 0
  /// when loadConst -time 0.0 reset OpenSees's clock there.
  double start_time = 0.0;
  std::filesystem::path displacement;   ///< Node -dof 1 2 disp (required)
  std::filesystem::path velocity;       ///< Node -dof 1 2 vel (required)
  std::filesystem::path acceleration;   ///< Node -dof 1 2 accel (zero when absent)
  std::filesystem::path pore_pressure;  ///< Node -dof 3 vel of u–p nodes (zero when absent)
  std::filesystem::path stress;         ///< Element stress (required)
  std::filesystem::path strain;         ///< Element strain (from the displacements when absent)
};

// ----------------------------------------------------------------------------- FEM

/// Rayleigh damping given as a damping ratio ξ at two frequencies f1 < f2 (the usual
/// OpenSees input).
struct DampingRatio {
  double ratio = 0.0;                   ///< ξ, –
  std::array<double, 2> frequencies{};  ///< f1, f2, Hz
};

struct DampingSpec {
  double rayleigh_mass = 0.0;       ///< α_M of the mass-proportional Rayleigh damping, 1/s
  double rayleigh_stiffness = 0.0;  ///< β_K of the stiffness-proportional Rayleigh damping, s
  double local = 0.0;               ///< Cundall local damping coefficient α, –
  /// Set when the case gave the ratio form; rayleigh_mass and rayleigh_stiffness are then
  /// derived from it (rayleigh_coefficients).
  std::optional<DampingRatio> ratio;
};

/// The Rayleigh coefficients whose damping ratio ξ(ω) = α_M/(2ω) + β_K ω/2 equals ξ at
/// ω1 = 2π f1 and ω2 = 2π f2: α_M = 2ξ ω1 ω2/(ω1 + ω2) (1/s), β_K = 2ξ/(ω1 + ω2) (s).
/// Between the two frequencies ξ(ω) is below ξ, outside them above.
struct RayleighCoefficients {
  double mass = 0.0;       ///< α_M, 1/s
  double stiffness = 0.0;  ///< β_K, s
};
RayleighCoefficients rayleigh_coefficients(const DampingRatio& ratio);

/// One component of the base acceleration, [fem.motion.horizontal] or [...vertical].
struct MotionComponentSpec {
  MotionSource source = MotionSource::ricker;
  double scale = 1.0;           ///< m/s² per unit of the case's numbers (1, or 9.81 for g)
  double amplitude = 0.0;       ///< ricker, sine: peak acceleration, m/s²
  double peak_frequency = 0.0;  ///< ricker: f_p, Hz
  double peak_time = 0.0;       ///< ricker: τ_p, s after the motion's start
  double frequency = 0.0;       ///< sine: f, Hz
  double duration = 0.0;        ///< sine: D, s
  double taper = 0.0;           ///< sine: cosine taper at each end, s
  std::filesystem::path file;   ///< file: two columns, absolute path
};

/// [fem.motion]: base shaking of the failure stage (docs/method.md §8).
struct MotionSpec {
  double start_time = 0.0;  ///< s on the failure stage's clock when the shaking begins
  SeismicBase base = SeismicBase::rigid;
  LateralBoundary lateral = LateralBoundary::boundaries;
  MotionInput input = MotionInput::incident;  ///< compliant base only
  double rock_density = 0.0;                  ///< ρ_r, kg/m³ (compliant)
  double rock_shear_wave_speed = 0.0;         ///< V_s,r, m/s (compliant)
  double rock_p_wave_speed = 0.0;             ///< V_p,r, m/s (compliant, vertical motion)
  bool baseline_correction = true;
  std::optional<MotionComponentSpec> horizontal;
  std::optional<MotionComponentSpec> vertical;
};

/// [[fem.recorders]]: time histories written to OUT/recorders/<name>.csv. Node
/// recorders take the nodes nearest `points` or a node set; element recorders the
/// elements that contain `elements`.
struct RecorderSpec {
  std::string name;
  std::vector<Vec2> points;    ///< nodes nearest these points
  std::string node_set;        ///< or every node of this set
  std::vector<Vec2> elements;  ///< or the elements containing these points
  double every = 0.0;          ///< s between rows (0: every step)
};

struct FemSpec {
  /// False for geostatic-only cases: fem-solve stops after the t = 0 checkpoint.
  bool failure_stage = true;
  Kinematics kinematics = Kinematics::small_strain;
  double end_time = 0.0;                 ///< s
  std::vector<double> checkpoint_times;  ///< s, besides t = 0 and the end time
  double checkpoint_every = 0.0;         ///< s, 0: only the listed times
  double output_every = 0.0;             ///< history cadence, s (0: every checkpoint)
  /// VTK frame cadence, s (0: every output step); none given: about 100 frames a run
  /// (run::automatic_vtk_every)
  std::optional<double> vtk_every;
  double courant = 0.5;                ///< C in dt = C·min(l_e/c_p)
  double time_step = 0.0;              ///< fixed dt, s (0: Courant)
  double hourglass_coefficient = 1.0;  ///< scale of the physical hourglass stiffness
  BoundaryTable geostatic_boundaries;  ///< stage 1
  BoundaryTable failure_boundaries;    ///< stage 2
  double friction_coefficient = 0.0;   ///< μ of "friction" boundaries
  DampingSpec damping;
  /// Instability guard: speeds above this factor × sqrt(2 g H) stop the run.
  double speed_limit_factor = 5.0;
  std::optional<MotionSpec> motion;  ///< base shaking (none: a static base)
  std::vector<RecorderSpec> recorders;
};

// ----------------------------------------------------------------------------- transfer

struct TransferSpec {
  int particles_x = 4;          ///< N_px (quads)
  int particles_y = 4;          ///< N_py (quads)
  int particles_triangle = 16;  ///< points of the triangle rule
  StressInterpolation stress_interpolation = StressInterpolation::rbf;
  std::optional<RbfPolynomial> rbf_polynomial;  ///< unset: none for rbf, linear for rbf-local
  double rbf_shape = 0.0;                       ///< c, m (0: the default sqrt(A_box/N_g))
  int rbf_neighbours = 0;                       ///< k of rbf-local (0: the default)
  /// Transfer times the case's sweep uses, s (docs/method.md §7), and the one the main
  /// pipeline uses.
  std::vector<double> sweep_times;
  double main_time = 0.0;
};

// ----------------------------------------------------------------------------- MPM

struct MpmSpec {
  Vec2 domain_min = Vec2::Zero();  ///< lower-left corner of the grid, m
  Vec2 domain_max = Vec2::Zero();  ///< upper-right corner of the grid, m
  double cell_size = 1.0;          ///< h, m
  ShapeFunction shape_function = ShapeFunction::gimp;
  UpdateScheme update_scheme = UpdateScheme::musl;
  VelocityTransfer velocity_transfer = VelocityTransfer::flip_pic;
  /// 0: pure FLIP, 1: pure PIC; read with any transfer, used by flip-pic only (apic
  /// ignores it, so that switching the transfer is a one-line edit)
  double pic_fraction = 0.0;
  VolumetricSmoothing volumetric_smoothing = VolumetricSmoothing::none;
  double end_time = 0.0;  ///< s
  std::vector<double> checkpoint_times;
  double checkpoint_every = 0.0;  ///< s
  double output_every = 0.0;      ///< history cadence, s
  /// VTK frame cadence, s (0: every output step); none given: about 100 frames a run
  /// (run::automatic_vtk_every)
  std::optional<double> vtk_every;
  double courant = 0.5;
  double time_step = 0.0;    ///< fixed dt, s (0: Courant on the cell size)
  BoundaryTable boundaries;  ///< "left", "right", "base", "top" of the grid
  double friction_coefficient = 0.0;
  double local_damping = 0.0;  ///< Cundall α
  ParticleExit particle_exit = ParticleExit::freeze;
  /// Stop early once KE/PE0 stays below `rest_threshold` for `rest_duration` s
  /// (0: run to the end time).
  double rest_threshold = 0.0;
  double rest_duration = 0.0;
  double speed_limit_factor = 5.0;
  // Pure MPM (no particle file): particles per cell and the initial stress.
  int particles_x = 4;
  int particles_y = 4;
  InitialStress initial_stress = InitialStress::k0;
  double gravity_stage_duration = 0.0;  ///< s of damped elastic loading (InitialStress::gravity)
  double gravity_stage_damping = 0.0;   ///< local damping α during that stage
};

// ----------------------------------------------------------------------------- metrics

struct MetricsSpec {
  double initial_length = 0.0;  ///< L_0, m
  double initial_height = 0.0;  ///< H_0, m (τ_c = sqrt(H_0/g))
  double bin_width = 2.0;       ///< profile bins, m
  double profile_percentile = 99.0;
  /// Particles at or below this height are left out of the profile and the toe: the
  /// top of a foundation layer that stays in place (slope-cohesive), m. 0: none.
  double foundation_level = 0.0;
};

// ----------------------------------------------------------------------------- case

struct Case {
  std::filesystem::path file;  ///< the case file it was read from
  std::string name;
  std::string description;
  /// g, m/s²: (0, −9.81) (docs/method.md §2), or turned by [case] gravity_angle.
  Vec2 gravity = gravity_vector();
  MaterialTable materials;
  MeshSpec mesh;
  FemSpec fem;
  TransferSpec transfer;
  MpmSpec mpm;
  MetricsSpec metrics;
  std::optional<OpenSeesImportSpec> opensees;  ///< [opensees], when the case has it

  /// Index of the material called `name`; throws Error when there is none.
  std::int32_t material_index(std::string_view name) const;
};

/// The largest case file load_case reads: 4 MiB (the cases are a few kB; a Gmsh mesh
/// lives in its own file).
inline constexpr std::size_t max_case_file_bytes = std::size_t{4} << 20;

/// Reads and validates a case file; throws Error (file:line: key: problem) on any fault.
Case load_case(const std::filesystem::path& path);
/// Same, from text (tests); `source_name` stands in for the file name in messages.
Case parse_case(std::string_view text, const std::filesystem::path& source_name);

}  // namespace slide
