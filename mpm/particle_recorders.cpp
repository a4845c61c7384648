#include "mpm/particle_recorders.hpp"

#include <algorithm>
#include <array>
#include <limits>

#include <fmt/format.h>

namespace slide::mpm {

namespace {

constexpr std::size_t npos = std::numeric_limits<std::size_t>::max();
constexpr std::array dry_columns{"x",   "y",   "ux",  "uy",  "vx", "vy",
                                 "sxx", "syy", "szz", "sxy", "eq"};

/// The particle whose reference position x − u is nearest `point`, the lowest id among
/// equals, over every rank (collective).
std::int64_t nearest_particle(const Particles& particles, const Ranks& ranks, const Vec2& point) {
  double best = std::numeric_limits<double>::infinity();
  std::int64_t id = std::numeric_limits<std::int64_t>::max();
  for (std::size_t p = 0; p < particles.count(); ++p) {
    const double d = (particles.coordinates[p] - particles.displacement[p] - point).squaredNorm();
    if (d < best || (d == best && particles.id[p] < id)) {
      best = d;
      id = particles.id[p];
    }
  }
  const double nearest = ranks.min(best);
  // Ids are creation indices, below 2^53: exact as doubles.
  const double mine =
      best == nearest ? static_cast<double>(id) : std::numeric_limits<double>::infinity();
  return static_cast<std::int64_t>(ranks.min(mine));
}

}  // namespace

ParticleRecorders::ParticleRecorders(const MpmSolver& solver,
                                     const std::vector<ParticleRecorderSpec>& specs,
                                     std::filesystem::path folder)
    : folder_(std::move(folder)), water_(!solver.particles().excess_pore_pressure.empty()) {
  const Particles& particles = solver.particles();
  if (solver.ranks().sum(static_cast<double>(particles.count())) == 0.0 && !specs.empty()) {
    throw Error("mpm.recorders: the run has no particles to record");
  }
  for (const ParticleRecorderSpec& spec : specs) {
    run::check_recorder_name(spec.name, "mpm.recorders");
    std::vector<std::int64_t> followed;
    std::string header = "time";
    for (const Vec2& point : spec.points) {
      const std::int64_t id = nearest_particle(particles, solver.ranks(), point);
      followed.push_back(id);
      for (const char* q : dry_columns) header += fmt::format(",p{}_{}", id, q);
      if (water_) header += fmt::format(",p{}_p", id);
    }
    ids_.insert(ids_.end(), followed.begin(), followed.end());
    particles_.push_back(std::move(followed));
    files_.emplace_back(spec.name, std::move(header), spec.every);
  }
  std::ranges::sort(ids_);
  ids_.erase(std::unique(ids_.begin(), ids_.end()), ids_.end());
  rows_.assign(ids_.size(), npos);
}

void ParticleRecorders::bound(double duration, double step) {
  run::bound_recorders(files_, duration, step, "mpm.recorders");
}

void ParticleRecorders::resume(double time, const Logger& logger) {
  for (run::RecorderFile& file : files_) file.resume(folder_, time, logger);
}

void ParticleRecorders::locate(const Particles& particles) {
  const auto held = [&](std::size_t k) {
    return rows_[k] < particles.count() && particles.id[rows_[k]] == ids_[k];
  };
  bool moved = false;
  for (std::size_t k = 0; k < ids_.size(); ++k) moved = moved || !held(k);
  if (!moved) return;
  std::ranges::fill(rows_, npos);
  for (std::size_t p = 0; p < particles.count(); ++p) {
    const auto at = std::ranges::lower_bound(ids_, particles.id[p]);
    if (at != ids_.end() && *at == particles.id[p]) {
      rows_[static_cast<std::size_t>(at - ids_.begin())] = p;
    }
  }
}

void ParticleRecorders::record(const MpmSolver& solver) {
  const double t = solver.clock().time;
  if (std::ranges::none_of(files_, [&](const run::RecorderFile& f) { return f.due(t); })) return;
  const Particles& particles = solver.particles();
  locate(particles);
  // Every followed particle's values, summed over the ranks (the one that holds it gives
  // them, the others zeros), and how many ranks hold it.
  const std::size_t per = dry_columns.size() + (water_ ? 1 : 0);
  std::vector<double> values((per + 1) * ids_.size(), 0.0);
  for (std::size_t k = 0; k < ids_.size(); ++k) {
    const std::size_t p = rows_[k];
    if (p == npos) continue;
    double* v = &values[k * (per + 1)];
    const Vec2& x = particles.coordinates[p];
    const Vec2& u = particles.displacement[p];
    const Vec2& w = particles.velocity[p];
    const Vec4& s = particles.stress[p];
    const std::array own{
        x.x(), x.y(), u.x(), u.y(), w.x(), w.y(), s[0], s[1], s[2], s[3], particles.eps_q[p]};
    std::ranges::copy(own, v);
    if (water_) v[dry_columns.size()] = particles.pore_pressure[p];
    v[per] = 1.0;
  }
  solver.ranks().sum(values);
  for (std::size_t r = 0; r < files_.size(); ++r) {
    run::RecorderFile& file = files_[r];
    if (!file.due(t)) continue;
    file.begin_row(t);
    for (const std::int64_t id : particles_[r]) {
      const auto k = static_cast<std::size_t>(std::ranges::lower_bound(ids_, id) - ids_.begin());
      const double* v = &values[k * (per + 1)];
      for (std::size_t c = 0; c < per; ++c) {
        file.add(v[per] > 0.0 ? v[c] / v[per] : std::numeric_limits<double>::quiet_NaN());
      }
    }
    file.end_row();
  }
}

void ParticleRecorders::write(const Ranks& ranks) const {
  ranks.together([&] {
    if (!ranks.root()) return;
    for (const run::RecorderFile& file : files_) file.write(folder_);
  });
}

std::string ParticleRecorders::describe() const {
  std::string text;
  for (std::size_t r = 0; r < files_.size(); ++r) {
    if (!text.empty()) text += "; ";
    std::string ids;
    for (const std::int64_t id : particles_[r])
      ids += fmt::format("{}p{}", ids.empty() ? "" : " ", id);
    text += fmt::format(
        "{}: particles {}, {}", files_[r].name(), ids,
        files_[r].every() > 0.0 ? fmt::format("every {} s", files_[r].every()) : "every step");
  }
  return text;
}

}  // namespace slide::mpm
