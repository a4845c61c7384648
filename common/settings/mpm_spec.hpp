// The MPM phase's settings as a case gives them ([mpm] of case.toml): the grid, the
// algorithms, end time and outputs, boundaries, damping, rest detection and pure MPM's
// initial state. mpm-solve resolves them into the solver's MpmSettings.
#pragma once

#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "common/base/types.hpp"
#include "common/geometry/mesh.hpp"
#include "common/physics/algorithms.hpp"

namespace slide {

/// [[mpm.recorders]]: time histories of the particles nearest `points`, written to
/// OUT/recorders/<name>.csv (mpm/particle_recorders.hpp).
struct ParticleRecorderSpec {
  std::string name;
  std::vector<Vec2> points;  ///< m, compared with each particle's reference position x − u
  double every = 0.0;        ///< s between rows (0: every step)
};

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
  /// A reservoir outside the body ([mpm.reservoir], docs/method.md §10): its level, m
  /// (unset: none), and the water's density, kg/m³.
  std::optional<double> reservoir_level;
  double water_density = 1000.0;
  /// [mpm.pore_water]: the pore pressure of saturated particles stays as the transfer
  /// left it (false) or evolves undrained with the water's bulk modulus, Pa.
  bool undrained_pore_pressure = false;
  double water_bulk_modulus = 2.2e9;
  double reservoir_x_min = -std::numeric_limits<double>::infinity();  ///< its extent, m
  double reservoir_x_max = std::numeric_limits<double>::infinity();
  // Pure MPM (no particle file): particles per cell and the initial stress.
  int particles_x = 4;
  int particles_y = 4;
  InitialStress initial_stress = InitialStress::k0;
  double gravity_stage_duration = 0.0;  ///< s of damped elastic loading (InitialStress::gravity)
  double gravity_stage_damping = 0.0;   ///< local damping α during that stage
  std::vector<ParticleRecorderSpec> recorders;
};

}  // namespace slide
