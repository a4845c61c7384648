// The FE phase's settings as a case gives them ([fem] of case.toml, common/input/case-file.md):
// end time and outputs, time step, boundaries of the two stages, damping, the base motion
// of a shaken stage and the recorders. Plain values: the case reader fills them, fem-solve
// takes them, and neither the solver nor its stages see the case file.
#pragma once

#include <array>
#include <filesystem>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "common/base/types.hpp"
#include "common/geometry/mesh.hpp"
#include "common/physics/algorithms.hpp"

namespace slide {

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

/// [fem.water]: the pore water of saturated materials (docs/method.md §10). Below `level`
/// the materials with a porosity are u–p mixtures starting from hydrostatic pressure; the
/// faces on or above it, and the faces of `drained` node sets, keep the hydrostatic
/// pressure of the level; a `reservoir` wets the model's upward-facing boundary below its
/// surface (drained at the reservoir's pressure, which also loads the solid); every other
/// face is impermeable.
struct WaterSpec {
  double level = 0.0;  ///< elevation of the water table (phreatic level), m
  /// A water table that varies along x: points (x, y) with x increasing, linear between
  /// them and level beyond the ends (gravity along −y). Empty: the level above.
  std::vector<Vec2> profile;
  double density = 1000.0;           ///< ρ_w, kg/m³
  double bulk_modulus = 2.2e9;       ///< K_f, Pa
  double tension_limit = -100e3;     ///< the lowest pore pressure, Pa (suction negative)
  std::vector<std::string> drained;  ///< node sets where p is given
  std::optional<double> reservoir;   ///< elevation of a reservoir's free surface, m
  /// The x range the reservoir stands over (a reservoir on one side of a dam), m.
  double reservoir_x_min = -std::numeric_limits<double>::infinity();
  double reservoir_x_max = std::numeric_limits<double>::infinity();
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
  /// The geostatic stage's left and right edges tied (periodic: nodes at equal elevation
  /// share their displacement), the free field of an infinite layer or slope.
  bool geostatic_tied_sides = false;
  BoundaryTable failure_boundaries;   ///< stage 2
  double friction_coefficient = 0.0;  ///< μ of "friction" boundaries
  DampingSpec damping;
  /// Instability guard: speeds above this factor × sqrt(2 g H) stop the run.
  double speed_limit_factor = 5.0;
  std::optional<MotionSpec> motion;  ///< base shaking (none: a static base)
  std::optional<WaterSpec> water;    ///< pore water (none: every material dry)
  std::vector<RecorderSpec> recorders;
};

}  // namespace slide
