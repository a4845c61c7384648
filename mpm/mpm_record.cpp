#include "mpm/mpm_record.hpp"

#include <algorithm>
#include <array>
#include <limits>
#include <numeric>
#include <sstream>
#include <variant>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "common/base/error.hpp"

namespace slide::mpm {

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
  if (const Subdomain* domain = solver.subdomain()) {
    for (const int begin : domain->cuts().begin) {
      r.slab_cuts += fmt::format("{}{}", r.slab_cuts.empty() ? "" : " ", begin);
    }
    const Ranks& ranks = solver.ranks();
    const auto n = static_cast<std::size_t>(ranks.size());
    const auto rank = static_cast<std::size_t>(ranks.rank());
    std::vector<std::int64_t> held(2 * n, 0);
    held[rank] = static_cast<std::int64_t>(solver.particles().count() - clock.frozen);
    held[n + rank] = static_cast<std::int64_t>(clock.frozen);
    ranks.sum(std::span<std::int64_t>(held));
    r.slab_rows = fmt::format("{}", fmt::join(held, " "));
  }
  return r;
}

MpmRecord read_mpm_record(const ParticleCheckpoint& checkpoint, const std::string& source) {
  if (checkpoint.header.kind != CheckpointKind::mpm) {
    throw Error("{}: is a {} file, expected kind mpm: --restart takes an mpm-solve checkpoint",
                source, to_string(checkpoint.header.kind));
  }
  MpmRecord defaults;
  defaults.sorted_once = true;
  MpmRecord r = run::read_record(checkpoint.solver, record_table, source, defaults);
  if (const auto cuts = checkpoint.solver.find("slab_cuts"); cuts != checkpoint.solver.end()) {
    const auto* text = std::get_if<std::string>(&cuts->second);
    if (text == nullptr) {
      throw Error("{}: /solver attribute slab_cuts is not a string of cell columns", source);
    }
    r.slab_cuts = *text;
  }
  if (const auto rows = checkpoint.solver.find("slab_rows"); rows != checkpoint.solver.end()) {
    const auto* text = std::get_if<std::string>(&rows->second);
    if (text == nullptr) {
      throw Error("{}: /solver attribute slab_rows is not a string of row counts", source);
    }
    r.slab_rows = *text;
  }
  if (static_cast<std::size_t>(r.frozen_particles) > checkpoint.file_rows) {
    throw Error(
        "{}: /solver attribute frozen_particles = {} is out of range (the file has {} "
        "particles)",
        source, r.frozen_particles, checkpoint.file_rows);
  }
  return r;
}

void restore(const MpmRecord& r, const CheckpointHeader& header, SolverClock& clock,
             RunReferences& references) {
  clock.time = header.time;
  clock.step = header.step;
  clock.previous_dt = r.previous_time_step;
  clock.steps_since_sort = r.steps_since_sort;
  clock.sorted_once = r.sorted_once;
  clock.frozen = static_cast<std::size_t>(r.frozen_particles);
  clock.boundary_work = r.boundary_work.value_or(0.0);
  references.pe0 = header.pe0;
  references.reference_height = r.reference_height;
  references.energy = *r.energy();
  references.rest_timer = r.rest_timer;
  references.time_step = r.time_step;
  references.courant = r.courant;
}

SolverSettings ran_with(const MpmSettings& settings, double time_step, double courant) {
  return settings_record(settings, time_step, courant);
}

SolverSettings write_record(const MpmSolver& solver, const RunReferences& references) {
  const MpmRecord record = restart_record(solver, references);
  SolverSettings settings =
      run::merged(ran_with(solver.settings(), references.time_step, references.courant),
                  run::write_record(record, record_table));
  if (!record.slab_cuts.empty()) settings["slab_cuts"] = record.slab_cuts;
  if (!record.slab_rows.empty()) settings["slab_rows"] = record.slab_rows;
  return settings;
}

namespace {

/// The whole numbers of `text`, or none when it holds anything else.
std::optional<std::vector<std::int64_t>> whole_numbers(const std::string& text) {
  std::vector<std::int64_t> numbers;
  std::istringstream in(text);
  for (long long number = 0; in >> number;) numbers.push_back(number);
  if (!in.eof()) return std::nullopt;
  return numbers;
}

}  // namespace

std::optional<Decomposition> restart_slabs(const MpmRecord& record, std::size_t file_rows,
                                           std::size_t first_row, int ranks,
                                           const std::string& source) {
  if (record.slab_cuts.empty()) return std::nullopt;
  const auto columns = whole_numbers(record.slab_cuts);
  if (!columns || columns->size() < 2 ||
      std::any_of(columns->begin(), columns->end(),
                  [](std::int64_t c) { return c < 0 || c > std::numeric_limits<int>::max(); })) {
    throw Error("{}: /solver attribute slab_cuts = \"{}\" is not a list of cell columns", source,
                record.slab_cuts);
  }
  Decomposition decomposition;
  decomposition.cuts.emplace();
  for (const std::int64_t c : *columns) decomposition.cuts->begin.push_back(static_cast<int>(c));
  if (decomposition.cuts->ranks() != ranks) return std::nullopt;
  // Written before the rows were recorded: the particles go to the slabs of their cells.
  if (record.slab_rows.empty()) return decomposition;
  const auto rows = whole_numbers(record.slab_rows);
  const auto n = static_cast<std::size_t>(ranks);
  if (!rows || rows->size() != 2 * n ||
      std::any_of(rows->begin(), rows->end(), [](std::int64_t r) { return r < 0; }) ||
      std::accumulate(rows->begin(), rows->end(), std::int64_t{0}) !=
          static_cast<std::int64_t>(file_rows) ||
      std::accumulate(rows->begin() + static_cast<std::ptrdiff_t>(n), rows->end(),
                      std::int64_t{0}) != record.frozen_particles) {
    throw Error(
        "{}: /solver attribute slab_rows = \"{}\" is not {} ranks' active then frozen row "
        "counts summing to the file's {} rows",
        source, record.slab_rows, ranks, file_rows);
  }
  HeldRows& held = decomposition.held.emplace();
  held.active.assign(rows->begin(), rows->begin() + static_cast<std::ptrdiff_t>(n));
  held.frozen.assign(rows->begin() + static_cast<std::ptrdiff_t>(n), rows->end());
  held.first_row = first_row;
  return decomposition;
}

}  // namespace slide::mpm
