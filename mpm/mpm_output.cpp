#include "mpm/mpm_output.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <sstream>

#include <fmt/format.h>

#include "common/base/error.hpp"
#include "common/base/program.hpp"
#include "common/physics/runout_metrics.hpp"
#include "mpm/mpm_record.hpp"

namespace slide::mpm {

namespace fs = std::filesystem;

void write_mpm_checkpoint(const fs::path& path, MpmSolver& solver, const RunReferences& references,
                          const std::string& case_name, const TransferSettings& transfer,
                          const std::optional<CheckpointMotion>& motion,
                          const SolverSettings& fingerprint) {
  ParticleCheckpoint c;
  c.header.kind = CheckpointKind::mpm;
  c.header.producer = "mpm-solve (" + version_string() + ")";
  c.header.time = solver.clock().time;
  c.header.step = solver.clock().step;
  c.header.case_name = case_name;
  c.header.pe0 = references.pe0;
  c.materials = solver.materials();
  c.transfer = transfer;
  c.motion = motion;
  c.solver = run::merged(write_record(solver, references), fingerprint);
  // Borrow the arrays (moves, no copy) and give them back whatever the write does.
  c.particles = solver.lend_particles();
  try {
    write_checkpoint_on_ranks(path, c, solver.clock().frozen, solver.ranks());
  } catch (...) {
    solver.return_particles(std::move(c.particles));
    throw;
  }
  solver.return_particles(std::move(c.particles));
}

// ----------------------------------------------------------------------------- history

MpmHistory::MpmHistory(fs::path path, const MetricsSpec& metrics)
    : csv_(std::move(path), {"time", "kinetic_energy", "pe0", "ke_over_pe0", "x_toe", "runout",
                             "runout_normalised", "x_front_95", "max_speed"}),
      metrics_(metrics) {}

void MpmHistory::write(const MpmSolver& solver, double pe0) {
  const double time = solver.clock().time;
  if (!csv_.rows().empty() && time <= csv_.rows().back().front()) return;
  const Energies e = solver.energies();
  // Positions from the base (a shaken run's grid moves with it), every rank's on the
  // root, which alone writes the file: x, y, mass, volume and speed of each.
  const Vec2 shift = solver.base_shift(time);
  const Particles& p = solver.particles();
  std::vector<std::array<double, 5>> from_base(p.count());
  for (std::size_t k = 0; k < p.count(); ++k) {
    from_base[k] = {p.coordinates[k].x() - shift.x(), p.coordinates[k].y() - shift.y(), p.mass[k],
                    p.volume[k], p.velocity[k].norm()};
  }
  const Ranks& ranks = solver.ranks();
  const auto gathered = Ranks::values_of<std::array<double, 5>>(
      ranks.gather_to_root(Ranks::bytes_of(std::span<const std::array<double, 5>>(from_base))));
  if (!ranks.root()) return;
  std::vector<Vec2> positions(gathered.size());
  std::vector<double> masses(gathered.size()), volumes(gathered.size());
  double max_speed = 0.0;
  for (std::size_t k = 0; k < gathered.size(); ++k) {
    positions[k] = Vec2(gathered[k][0], gathered[k][1]);
    masses[k] = gathered[k][2];
    volumes[k] = gathered[k][3];
    max_speed = std::max(max_speed, gathered[k][4]);
  }
  const SurfaceProfile profile = surface_profile(
      positions, metrics_.bin_width, metrics_.profile_percentile, metrics_.foundation_level);
  const RunoutMeasures m = runout_measures(profile, metrics_.initial_length);
  const FrontMeasures f =
      front_measures(positions, masses, volumes, profile, metrics_.foundation_level);
  csv_.add({time, e.kinetic, pe0, e.kinetic / pe0, m.x_toe, m.runout, m.runout_normalised,
            f.x_front, max_speed});
}

// ----------------------------------------------------------------------------- VTK

VtkWriter::VtkWriter(const fs::path& output_dir, std::optional<double> resume_time)
    : folder_(output_dir / "vtk"), collection_(output_dir / "mpm.pvd") {
  fs::create_directories(folder_);
  if (resume_time) collection_.resume(*resume_time);
}

namespace {

/// A saturated transfer's fields (docs/method.md §10), on every rank when any has them (a
/// rank without particles has them empty, and its piece must name the same arrays).
void add_pore_water_fields(std::vector<VtkField>& fields, const Particles& p, const Ranks& ranks) {
  if (ranks.max(p.liquefied.empty() ? 0.0 : 1.0) == 0.0) return;
  fields.push_back(vtk_field("excess_pore_pressure", p.excess_pore_pressure));
  fields.push_back(vtk_field("max_pore_pressure_ratio", p.max_pore_pressure_ratio));
  fields.push_back(vtk_field("liquefied", p.liquefied));
}

}  // namespace

void VtkWriter::write(const MpmSolver& solver) {
  const Particles& p = solver.particles();
  const std::size_t n = p.count();
  std::vector<std::uint8_t> active(n);
  std::vector<double> pressure(n), von_mises(n), plastic_shear(n), plastic_volumetric(n);
  for (std::size_t k = 0; k < n; ++k) {
    active[k] = k < solver.active_count() ? 1 : 0;
    pressure[k] = mean_stress(p.stress[k]);  // compression positive
    von_mises[k] = von_mises_stress(p.stress[k]);
    plastic_shear[k] = p.state[k].plastic_shear_strain;
    plastic_volumetric[k] = p.state[k].plastic_volumetric_strain;
  }
  const Ranks& ranks = solver.ranks();
  const std::string name = fmt::format("mpm_{:06d}", solver.clock().step);
  std::vector<VtkField> fields{vtk_field("displacement", p.displacement),
                               vtk_field("velocity", p.velocity),
                               vtk_field("stress", p.stress),
                               vtk_field("strain", p.strain),
                               vtk_field("eps_q", p.eps_q),
                               vtk_field("pressure", pressure),
                               vtk_field("von_mises_stress", von_mises),
                               vtk_field("pore_pressure", p.pore_pressure),
                               vtk_field("volume", p.volume),
                               vtk_field("mass", p.mass),
                               vtk_field("size", p.size),
                               vtk_field("material_id", p.material_id),
                               vtk_field("id", p.id),
                               vtk_field("element", p.element),
                               vtk_field("active", std::span<const std::uint8_t>(active)),
                               vtk_field("plastic_shear_strain", plastic_shear),
                               vtk_field("plastic_volumetric_strain", plastic_volumetric)};
  add_pore_water_fields(fields, p, ranks);
  if (!p.affine_velocity.empty()) {
    fields.push_back(vtk_field("affine_velocity_gradient", p.affine_velocity,  // APIC's C_p
                               VtkLayout::matrix));
  }
  // On several ranks each writes its piece and the root the .pvtu that joins them.
  if (!ranks.distributed()) {
    const fs::path file = folder_ / (name + ".vtu");
    write_vtk_points(file, solver.clock().time, p.coordinates, fields);
    collection_.add(solver.clock().time, fs::path("vtk") / file.filename());
    return;
  }
  write_pieces(ranks, name, solver.clock().time, p.coordinates, fields);
}

void VtkWriter::write_pieces(const Ranks& ranks, const std::string& name, double time,
                             std::span<const Vec2> coordinates,
                             const std::vector<VtkField>& fields) {
  // Every piece is in place before the collection names it; a piece that failed (a full
  // disk) ends every rank here.
  const fs::path file = folder_ / fmt::format("{}_r{}.vtu", name, ranks.rank());
  ranks.together([&] { write_vtk_points(file, time, coordinates, fields); });
  ranks.together([&] {
    if (!ranks.root()) return;
    std::vector<std::string> pieces;
    for (int r = 0; r < ranks.size(); ++r) pieces.push_back(fmt::format("{}_r{}.vtu", name, r));
    const fs::path joined = folder_ / (name + ".pvtu");
    write_vtk_points_collection(joined, pieces, fields);
    collection_.add(time, fs::path("vtk") / joined.filename());
  });
}

}  // namespace slide::mpm
