#include "mpm/mpm_output.hpp"

#include <array>
#include <cmath>
#include <limits>
#include <sstream>

#include <fmt/format.h>

#include "common/base/error.hpp"
#include "common/base/program.hpp"
#include "common/run/restart_record.hpp"
#include "common/physics/runout_metrics.hpp"

namespace slide::mpm {

namespace fs = std::filesystem;

namespace {

std::string_view exit_name(ParticleExit e) {
  return e == ParticleExit::freeze ? "freeze" : "remove";
}

/// The settings a run used, as stored in /solver.
SolverSettings settings_record(const MpmSettings& s, double time_step, double courant) {
  SolverSettings r;
  r["stage"] = std::string("mpm");
  r["domain_min_x"] = s.grid.origin.x();
  r["domain_min_y"] = s.grid.origin.y();
  r["cells_x"] = std::int64_t{s.grid.cells_x};
  r["cells_y"] = std::int64_t{s.grid.cells_y};
  r["cell_size"] = s.grid.cell_size;
  r["shape_function"] = std::string(to_string(s.shape_function));
  r["update_scheme"] = std::string(to_string(s.update_scheme));
  r["velocity_transfer"] = std::string(to_string(s.velocity_transfer));
  r["pic_fraction"] = s.pic_fraction;
  r["volumetric_smoothing"] = std::string(to_string(s.volumetric_smoothing));
  r["local_damping"] = s.damping.local;
  r["friction_coefficient"] = s.boundaries.friction_coefficient;
  const char* edges[] = {"left", "right", "base", "top"};
  for (int e = 0; e < 4; ++e) {
    r[fmt::format("boundary_{}", edges[e])] =
        std::string(to_string(s.boundaries.edge[static_cast<std::size_t>(e)].condition));
  }
  r["particle_exit"] = std::string(exit_name(s.particle_exit));
  r["sort_interval"] = std::int64_t{s.sort_interval};
  r["time_step"] = time_step;
  r["courant"] = courant;
  return r;
}

/// The restart record's entries (common/run/restart_record.hpp), each checked on reading.
constexpr std::array<run::RecordEntry<MpmRecord>, 12> record_table{{
    {"stage", &MpmRecord::stage},
    {"previous_time_step", &MpmRecord::previous_time_step, 0.0},
    {"steps_since_sort", &MpmRecord::steps_since_sort, 0.0},
    // Absent in checkpoints of earlier versions: sorted (checkpointed after steps).
    {"sorted_once", &MpmRecord::sorted_once, 0.0, 1.0, run::Need::optional},
    {"frozen_particles", &MpmRecord::frozen_particles, 0.0},
    {"reference_height", &MpmRecord::reference_height, 0.0},
    {"initial_energy", &MpmRecord::initial_energy},
    {"energy_scale", &MpmRecord::energy_scale, 0.0},
    {"rest_timer", &MpmRecord::rest_timer, 0.0},
    {"time_step", &MpmRecord::time_step, 0.0},
    // Absent before the step followed the particles' current density (the step itself
    // was stored, no Courant number).
    {"courant", &MpmRecord::courant, 0.0, run::unbounded, run::Need::optional},
    // Shaken runs only.
    {"boundary_work", &MpmRecord::boundary_work, -run::unbounded, run::unbounded,
     run::Need::optional},
}};

}  // namespace

MpmRecord restart_record(const MpmSolver& solver, const RunReferences& references) {
  const SolverClock& clock = solver.clock();
  MpmRecord r;
  r.stage = "mpm";
  r.previous_time_step = clock.previous_dt;
  r.steps_since_sort = clock.steps_since_sort;
  // false in the checkpoint a run writes at its start, before its first step sorts: a
  // restart from it then sorts too, and continues bit for bit.
  r.sorted_once = clock.sorted_once;
  // The file's count: every rank's frozen particles (they are the file's last rows).
  r.frozen_particles =
      static_cast<std::int64_t>(solver.ranks().sum(static_cast<double>(clock.frozen)));
  r.reference_height = references.reference_height;
  r.set_energy(references.energy);
  r.rest_timer = references.rest_timer;
  r.time_step = references.time_step;
  r.courant = references.courant;
  if (solver.base_motion()) r.boundary_work = clock.boundary_work;
  return r;
}

void write_mpm_checkpoint(const fs::path& path, MpmSolver& solver, const RunReferences& references,
                          const std::string& case_name, const TransferSettings& transfer,
                          const std::optional<CheckpointMotion>& motion) {
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
  c.solver = run::merged(ran_with(solver.settings(), references.time_step, references.courant),
                         run::write_record(restart_record(solver, references), record_table));
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

void read_restart_state(const ParticleCheckpoint& checkpoint, const std::string& source,
                        SolverClock& clock, RunReferences& references) {
  if (checkpoint.header.kind != CheckpointKind::mpm) {
    throw Error("{}: is a {} file; --restart takes an mpm-solve checkpoint (kind mpm)", source,
                to_string(checkpoint.header.kind));
  }
  MpmRecord defaults;
  defaults.sorted_once = true;
  const MpmRecord r = run::read_record(checkpoint.solver, record_table, source, defaults);
  if (static_cast<std::size_t>(r.frozen_particles) > checkpoint.file_rows) {
    throw Error("{}: /solver attribute frozen_particles = {} is out of range (the file has {} "
                "particles)",
                source, r.frozen_particles, checkpoint.file_rows);
  }
  clock.time = checkpoint.header.time;
  clock.step = checkpoint.header.step;
  clock.previous_dt = r.previous_time_step;
  clock.steps_since_sort = r.steps_since_sort;
  clock.sorted_once = r.sorted_once;
  clock.frozen = static_cast<std::size_t>(r.frozen_particles);
  clock.boundary_work = r.boundary_work.value_or(0.0);
  references.pe0 = checkpoint.header.pe0;
  references.reference_height = r.reference_height;
  references.energy = *r.energy();
  references.rest_timer = r.rest_timer;
  references.time_step = r.time_step;
  references.courant = r.courant;
}

SolverSettings ran_with(const MpmSettings& settings, double time_step, double courant) {
  return settings_record(settings, time_step, courant);
}

// ----------------------------------------------------------------------------- history

MpmHistory::MpmHistory(fs::path path, const MetricsSpec& metrics)
    : csv_(std::move(path), {"time", "kinetic_energy", "pe0", "ke_over_pe0", "x_toe", "runout",
                             "runout_normalised"}),
      metrics_(metrics) {}

void MpmHistory::write(const MpmSolver& solver, double pe0) {
  const double time = solver.clock().time;
  if (!csv_.rows().empty() && time <= csv_.rows().back().front()) return;
  const Energies e = solver.energies();
  // Positions from the base (a shaken run's grid moves with it), every rank's on the
  // root, which alone writes the file.
  const Vec2 shift = solver.base_shift(time);
  const auto& x = solver.particles().coordinates;
  std::vector<std::array<double, 2>> from_base(x.size());
  for (std::size_t k = 0; k < x.size(); ++k)
    from_base[k] = {x[k].x() - shift.x(), x[k].y() - shift.y()};
  const Ranks& ranks = solver.ranks();
  const auto gathered = Ranks::values_of<std::array<double, 2>>(
      ranks.gather_to_root(Ranks::bytes_of(std::span<const std::array<double, 2>>(from_base))));
  if (!ranks.root()) return;
  std::vector<Vec2> positions(gathered.size());
  for (std::size_t k = 0; k < gathered.size(); ++k)
    positions[k] = Vec2(gathered[k][0], gathered[k][1]);
  const SurfaceProfile profile = surface_profile(
      positions, metrics_.bin_width, metrics_.profile_percentile, metrics_.foundation_level);
  const RunoutMeasures m = runout_measures(profile, metrics_.initial_length);
  csv_.add({time, e.kinetic, pe0, e.kinetic / pe0, m.x_toe, m.runout, m.runout_normalised});
}

// ----------------------------------------------------------------------------- VTK

VtkWriter::VtkWriter(const fs::path& output_dir, std::optional<double> resume_time)
    : folder_(output_dir / "vtk"), collection_(output_dir / "mpm.pvd") {
  fs::create_directories(folder_);
  if (resume_time) collection_.resume(*resume_time);
}

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
  // On several ranks each writes its piece and the root the .pvtu that joins them.
  const fs::path file =
      folder_ /
      (ranks.distributed() ? fmt::format("{}_r{}.vtu", name, ranks.rank()) : name + ".vtu");
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
  if (!p.affine_velocity.empty()) {
    fields.push_back(vtk_field("affine_velocity_gradient", p.affine_velocity,  // APIC's C_p
                               VtkLayout::matrix));
  }
  write_vtk_points(file, solver.clock().time, p.coordinates, fields);
  if (!ranks.distributed()) {
    collection_.add(solver.clock().time, fs::path("vtk") / file.filename());
    return;
  }
  ranks.barrier();  // every piece is in place before the collection names it
  if (!ranks.root()) return;
  std::vector<std::string> pieces;
  for (int r = 0; r < ranks.size(); ++r) pieces.push_back(fmt::format("{}_r{}.vtu", name, r));
  const fs::path joined = folder_ / (name + ".pvtu");
  write_vtk_points_collection(joined, pieces, fields);
  collection_.add(solver.clock().time, fs::path("vtk") / joined.filename());
}

}  // namespace slide::mpm
