// Particles → CB-Geo MPM input (mpm2cbgeo; tools/interop/README.md).
//
// From a particle file (fem2mpm) or an mpm checkpoint and the case that made it, the
// input of a 2D explicit CB-Geo MPM run that starts from the same particles on the same
// background grid, in CB-Geo's ASCII formats:
//   mesh.txt                "n_nodes n_cells", then x y per node, then the 4 node ids
//                           (0-based, counter-clockwise from the lower left: ED2Q4) per
//                           cell: the case's mpm.domain cut into mpm.cell_size squares
//   particles-<m>.txt       "n", then x y per particle of material m (one file each)
//   particles-stresses.txt  "n", then σxx σyy σzz τxy τyz τxz per particle, in CB-Geo's
//                           particle order (material by material, file order within)
//   particles-volumes.txt   "id V" per particle, V = M_p/ρ so that CB-Geo's mass ρV is
//                           the particle's mass
//   entity_sets.json        node sets 0 left, 1 right, 2 base, 3 top of the grid
//   mpm.json                the input: mesh and its constraints (the case's
//                           mpm.boundaries: rollers and fixed as velocity constraints,
//                           friction as a friction constraint), one file generator per
//                           material, the materials (Mohr–Coulomb as MohrCoulomb2D with
//                           no softening, linear elastic as LinearElastic2D), gravity,
//                           and the analysis (MPMExplicit2D, USF or USL, the Courant step
//                           of the particles, the steps to the case's end time, Cundall
//                           damping, output cadence).
// What CB-Geo's ASCII input cannot carry (velocities, strains, plastic state, APIC,
// GIMP domains, MUSL), and what the case sets that mpm.json does not hold (the base
// motion, gravity_angle, the rest stop...), is listed by the export and in the README's
// table.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "common/input/case_file.hpp"
#include "common/io/checkpoint.hpp"

namespace slide::interop {

struct CbGeoExportOptions {
  double end_time = 0.0;      ///< s on the project's clock; 0: the case's mpm.end_time
  double output_every = 0.0;  ///< s between CB-Geo's HDF5 outputs; 0: mpm.checkpoint_every
  /// Courant number of CB-Geo's fixed step C h / max c_p at the particles' present
  /// density (a case's mpm.time_step wins). Not the case's 0.5: CB-Geo keeps its step for
  /// the whole run while the runout front spreads, and on column-short its front particles
  /// grew to 24 times their volume by t = 2.8 s, which multiplies c_p by 4.9; at C = 0.5
  /// the run blew up within 30 steps, at 0.25 between 2 and 4 s (tools/interop/README.md).
  double courant = 0.05;
  /// CB-Geo's update scheme: "usl" (the nearest to the project's MUSL) or "usf".
  std::string scheme = "usl";
};

/// One particle as CB-Geo's HDF5 particle table holds it (the fields it reads back on a
/// resume, in the order of its table; 2D: the z components are zero).
struct CbGeoParticle {
  std::int64_t id = 0;
  double mass = 0.0, volume = 0.0, pressure = 0.0;
  double coordinates[3] = {0, 0, 0};
  double displacement[3] = {0, 0, 0};
  double natural_size[3] = {0, 0, 0};
  double velocity[3] = {0, 0, 0};
  double stress[6] = {0, 0, 0, 0, 0, 0};  ///< xx yy zz xy yz xz
  double strain[6] = {0, 0, 0, 0, 0, 0};  ///< xx yy zz γxy γyz γxz
  double volumetric_strain = 0.0;
  std::uint8_t status = 1;
  std::int64_t cell = 0;
  std::uint32_t material = 0;
  std::uint32_t state_variables = 0;  ///< 0: CB-Geo initialises them from the material
  double state[20] = {};
};

/// The files of one export: name → text, and the particle table CB-Geo resumes from.
struct CbGeoInput {
  std::vector<std::pair<std::string, std::string>> files;
  /// results/<uuid>/particles<0…0>.h5: CB-Geo's own output format at step 0, which
  /// mpm.json's analysis.resume reads (velocities and strains included).
  std::string resume_file;
  std::vector<CbGeoParticle> resume_particles;
  std::vector<std::string> notes;  ///< what does not carry over, for the log
  double time_step = 0.0;          ///< s
  long steps = 0;
};

/// Builds the input, and in `notes` every setting of the case and every part of the
/// particles' state that it does not carry over (the base motion, a turned gravity, the
/// algorithms CB-Geo has not...). Error on a particle outside the grid, an end time before
/// the particles' time, an output cadence shorter than CB-Geo's step or of more than 10⁵
/// outputs, more than run::max_steps steps, a number of mpm.json that is not finite.
CbGeoInput export_cbgeo(const Case& c, const ParticleCheckpoint& particles,
                        const CbGeoExportOptions& options);

/// Writes `particles` as CB-Geo's HDF5 particle table (dataset "table") atomically.
void write_cbgeo_particles(const std::filesystem::path& path,
                           const std::vector<CbGeoParticle>& particles);

}  // namespace slide::interop
