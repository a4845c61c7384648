#include "mpm/mpm_output.hpp"

#include <array>
#include <cmath>
#include <limits>
#include <sstream>

#include <fmt/format.h>

#include "common/base/error.hpp"
#include "common/base/program.hpp"
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

std::string show(const SettingValue& v) {
  return std::visit([](const auto& x) { return fmt::format("{}", x); }, v);
}

template <class T>
T setting(const SolverSettings& s, const std::string& key, const std::string& source) {
  const auto found = s.find(key);
  if (found == s.end())
    throw Error("{}: /solver attribute {} missing (not an mpm-solve checkpoint?)", source, key);
  if (const T* value = std::get_if<T>(&found->second)) return *value;
  throw Error("{}: /solver attribute {} has the wrong type", source, key);
}

}  // namespace

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
  c.solver = settings_record(solver.settings(), references.time_step, references.courant);
  const SolverClock& clock = solver.clock();
  c.solver["previous_time_step"] = clock.previous_dt;
  c.solver["steps_since_sort"] = clock.steps_since_sort;
  // 0 in the checkpoint a run writes at its start, before its first step sorts: a
  // restart from it then sorts too, and continues bit for bit.
  c.solver["sorted_once"] = std::int64_t{clock.sorted_once ? 1 : 0};
  const Ranks& ranks = solver.ranks();
  // The file's count: every rank's frozen particles (they are the file's last rows).
  c.solver["frozen_particles"] =
      static_cast<std::int64_t>(ranks.sum(static_cast<double>(clock.frozen)));
  c.solver["reference_height"] = references.reference_height;
  c.solver["initial_energy"] = references.energy.initial_energy;
  c.solver["energy_scale"] = references.energy.energy_scale;
  c.solver["rest_timer"] = references.rest_timer;
  if (motion) {
    c.motion = motion;
    c.solver["boundary_work"] = clock.boundary_work;
  }
  // Borrow the arrays (moves, no copy) and give them back whatever the write does.
  c.particles = solver.lend_particles();
  try {
    write_checkpoint_on_ranks(path, c, clock.frozen, ranks);
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
  const SolverSettings& s = checkpoint.solver;
  // Every counter and reference is checked here, so that a damaged value is named at
  // once instead of surfacing later as a misleading failure (a NaN step as a
  // "non-finite position").
  const auto at_least = [&](const std::string& key, double low) {
    const double value = setting<double>(s, key, source);
    if (!(std::isfinite(value) && value >= low)) {
      throw Error("{}: /solver attribute {} = {} is out of range (expected a finite value ≥ {})",
                  source, key, value, low);
    }
    return value;
  };
  clock.time = checkpoint.header.time;
  clock.step = checkpoint.header.step;
  clock.previous_dt = at_least("previous_time_step", 0.0);
  clock.steps_since_sort = setting<std::int64_t>(s, "steps_since_sort", source);
  if (clock.steps_since_sort < 0) {
    throw Error("{}: /solver attribute steps_since_sort = {} is out of range (expected ≥ 0)",
                source, clock.steps_since_sort);
  }
  // Checkpoints written before the key existed: sorted (a run checkpointed after steps).
  clock.sorted_once = true;
  if (s.contains("sorted_once")) {
    const auto sorted = setting<std::int64_t>(s, "sorted_once", source);
    if (sorted != 0 && sorted != 1) {
      throw Error("{}: /solver attribute sorted_once = {} is out of range (expected 0 or 1)",
                  source, sorted);
    }
    clock.sorted_once = sorted == 1;
  }
  const auto frozen = setting<std::int64_t>(s, "frozen_particles", source);
  if (frozen < 0 || static_cast<std::size_t>(frozen) > checkpoint.particles.count()) {
    throw Error("{}: /solver attribute frozen_particles = {} is out of range", source, frozen);
  }
  clock.frozen = static_cast<std::size_t>(frozen);
  if (s.contains("boundary_work")) {
    clock.boundary_work = setting<double>(s, "boundary_work", source);
    if (!std::isfinite(clock.boundary_work)) {
      throw Error("{}: /solver attribute boundary_work = {} is not finite", source,
                  clock.boundary_work);
    }
  }
  references.pe0 = checkpoint.header.pe0;
  references.reference_height = at_least("reference_height", 0.0);
  references.energy.initial_energy =
      at_least("initial_energy", std::numeric_limits<double>::lowest());
  references.energy.energy_scale = at_least("energy_scale", 0.0);
  references.rest_timer = at_least("rest_timer", 0.0);
  references.time_step = at_least("time_step", 0.0);
  // Checkpoints before the step followed the particles' current density stored the
  // step itself and no Courant number.
  if (s.contains("courant")) references.courant = at_least("courant", 0.0);
}

std::vector<std::string> changed_settings(const SolverSettings& stored, const MpmSettings& settings,
                                          double time_step, double courant) {
  std::vector<std::string> changes;
  for (const auto& [key, value] : settings_record(settings, time_step, courant)) {
    const auto found = stored.find(key);
    if (found == stored.end()) continue;
    if (found->second != value)
      changes.push_back(fmt::format("{} {} → {}", key, show(found->second), show(value)));
  }
  return changes;
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
