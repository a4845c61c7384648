#include "common/input/case_fingerprint.hpp"

#include <algorithm>
#include <cstdint>
#include <fstream>
#include <vector>

#include <fmt/format.h>

#include "common/base/error.hpp"

namespace slide {

namespace {

constexpr std::string_view prefix = "case_";

/// FNV-1a (64 bit) of a file's bytes, as 16 hex digits ("missing" when it cannot be read).
std::string content_hash(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) return "missing";
  std::uint64_t hash = 14695981039346656037ULL;
  std::vector<char> chunk(1 << 16);
  while (in.read(chunk.data(), static_cast<std::streamsize>(chunk.size())) || in.gcount() > 0) {
    for (std::streamsize i = 0; i < in.gcount(); ++i) {
      hash ^= static_cast<unsigned char>(chunk[static_cast<std::size_t>(i)]);
      hash *= 1099511628211ULL;
    }
  }
  return fmt::format("{:016x}", hash);
}

std::string file_line(const std::filesystem::path& file) {
  return file.empty()
             ? std::string("none")
             : fmt::format("{} (content {})", file.filename().string(), content_hash(file));
}

std::string materials_line(const MaterialTable& materials) {
  std::string line;
  for (const Material& m : materials) {
    line += fmt::format("{}{}: {}/{} ρ {} E {} ν {} φ {} c {} ψ {} T {} γ_peak {} surfaces {}",
                        line.empty() ? "" : "; ", m.name, to_string(m.model),
                        to_string(m.model_of(Phase::mpm)), m.density, m.youngs_modulus,
                        m.poisson_ratio, m.friction_angle, m.cohesion, m.dilation_angle,
                        m.tension_cutoff, m.peak_shear_strain, m.yield_surfaces);
    if (m.uses(MaterialModel::pm4sand)) {
      const Pm4SandParameters& p = m.pm4sand;
      line += fmt::format(
          " pm4sand D_R {} G0 {} h_po {} p_A {} h0 {} e ({}, {}) n ({}, {}) A_do {} z_max {} c_z "
          "{} "
          "c_e {} φ_cv {} C_GD {} C_DR {} C_kaf {} Q {} R {} m {} step {}",
          p.relative_density, p.shear_modulus_coefficient, p.contraction_rate,
          p.atmospheric_pressure, p.h0, p.e_max, p.e_min, p.n_b, p.n_d, p.a_do, p.z_max, p.c_z,
          p.c_e, p.critical_friction_angle, p.c_gd, p.c_dr, p.c_kaf, p.q, p.r, p.m, p.strain_step);
    }
    if (m.liquefaction.enabled) {
      const LiquefactionParameters& q = m.liquefaction;
      line += fmt::format(
          " liquefaction r_u {} γ {} {} N {} ratio {} φ′ {} S_min {} peak {} γ_s {} G× {} ν {}",
          q.pore_pressure_ratio, q.shear_strain, to_string(q.correlation), q.blow_count,
          q.strength_ratio, q.friction_angle, q.minimum_strength, q.peak_strength_ratio,
          q.softening_strain, q.shear_modulus_ratio, q.poisson_ratio);
    }
    // Porous materials only, so that dry cases' fingerprints stay as they were.
    if (m.saturable()) {
      line += fmt::format(" n {} k ({}, {})", m.porosity, m.conductivity_x, m.conductivity_y);
    }
  }
  return line;
}

std::string table_line(const BoundaryTable& table) {
  std::string line;
  for (const auto& [name, condition] : table) {
    line += fmt::format("{}{} {}", line.empty() ? "" : ", ", name, to_string(condition));
  }
  return line.empty() ? "none" : line;
}

std::string mesh_line(const MeshSpec& mesh, const std::filesystem::path& case_file) {
  std::string line =
      fmt::format("{} element size {}", to_string(mesh.element_type), mesh.element_size);
  for (const Vec2& p : mesh.surface) line += fmt::format(" ({}, {})", p.x(), p.y());
  for (const MeshBlock& b : mesh.blocks) {
    line += fmt::format(" block {} {}×{}", b.material, b.cells_u, b.cells_v);
    for (const Vec2& p : b.corners) line += fmt::format(" ({}, {})", p.x(), p.y());
  }
  if (!mesh.file().empty()) {
    std::filesystem::path path = mesh.file();
    if (path.is_relative()) path = case_file.parent_path() / path;
    line += " file " + file_line(path);
  }
  return line;
}

std::string component_line(const MotionComponentSpec& c) {
  return fmt::format("{} scale {} A {} f {} t {} f_sine {} D {} taper {} file {}",
                     to_string(c.source), c.scale, c.amplitude, c.peak_frequency, c.peak_time,
                     c.frequency, c.duration, c.taper, file_line(c.file));
}

std::string motion_line(const std::optional<MotionSpec>& motion) {
  if (!motion) return "none";
  const MotionSpec& m = *motion;
  return fmt::format(
      "from {} s, {} base, {} sides, {} input, rock ρ {} V_s {} V_p {}, baseline {}; "
      "horizontal {}; vertical {}",
      m.start_time, to_string(m.base), to_string(m.lateral), to_string(m.input), m.rock_density,
      m.rock_shear_wave_speed, m.rock_p_wave_speed,
      m.baseline_correction ? "corrected" : "as given",
      m.horizontal ? component_line(*m.horizontal) : "none",
      m.vertical ? component_line(*m.vertical) : "none");
}

std::string recorders_line(const std::vector<RecorderSpec>& recorders) {
  std::string line;
  for (const RecorderSpec& r : recorders) {
    line += fmt::format("{}{}: every {}", line.empty() ? "" : "; ", r.name, r.every);
    if (!r.node_set.empty()) line += " node set " + r.node_set;
    for (const Vec2& p : r.points) line += fmt::format(" node ({}, {})", p.x(), p.y());
    for (const Vec2& p : r.elements) line += fmt::format(" element ({}, {})", p.x(), p.y());
  }
  return line.empty() ? "none" : line;
}

std::string gravity_line(const Vec2& g) {
  return fmt::format("({}, {}) m/s²", g.x(), g.y());
}

void add(SolverSettings& settings, std::string_view part, std::string line) {
  settings[std::string(prefix) + std::string(part)] = std::move(line);
}

}  // namespace

SolverSettings fem_fingerprint(const Case& c) {
  const FemSpec& f = c.fem;
  SolverSettings s;
  add(s, "materials", materials_line(c.materials));
  add(s, "gravity", gravity_line(c.gravity));
  add(s, "mesh", mesh_line(c.mesh, c.file));
  add(s, "boundaries",
      fmt::format("geostatic {}{}; failure {}; μ {}", table_line(f.geostatic_boundaries),
                  f.geostatic_tied_sides ? " tied sides" : "", table_line(f.failure_boundaries),
                  f.friction_coefficient));
  add(s, "damping",
      fmt::format("α_M {} β_K {} local {}", f.damping.rayleigh_mass, f.damping.rayleigh_stiffness,
                  f.damping.local));
  add(s, "time_step",
      fmt::format("{} kinematics, fixed {} s, C {}, hourglass {}", to_string(f.kinematics),
                  f.time_step, f.courant, f.hourglass_coefficient));
  add(s, "motion", motion_line(f.motion));
  add(s, "recorders", recorders_line(f.recorders));
  if (f.water) {  // saturated cases only (dry cases' fingerprints stay as they were)
    const WaterSpec& w = *f.water;
    std::string drained;
    for (const std::string& name : w.drained) drained += (drained.empty() ? "" : " ") + name;
    add(s, "water",
        fmt::format("level {} m, ρ_w {}, K_f {}, tension limit {}, drained [{}]{}", w.level,
                    w.density, w.bulk_modulus, w.tension_limit, drained,
                    w.reservoir ? fmt::format(", reservoir {} m", *w.reservoir) : ""));
    if (!w.profile.empty()) {
      std::string profile;
      for (const Vec2& p : w.profile) profile += fmt::format(" ({}, {})", p.x(), p.y());
      add(s, "water_table", profile);
    }
    if (w.reservoir && (std::isfinite(w.reservoir_x_min) || std::isfinite(w.reservoir_x_max))) {
      add(s, "reservoir_extent", fmt::format("{} to {} m", w.reservoir_x_min, w.reservoir_x_max));
    }
  }
  return s;
}

SolverSettings mpm_fingerprint(const Case& c, bool pure_mpm) {
  const MpmSpec& m = c.mpm;
  SolverSettings s;
  add(s, "materials", materials_line(c.materials));
  add(s, "gravity", gravity_line(c.gravity));
  add(s, "grid",
      fmt::format("({}, {})–({}, {}) cells of {} m", m.domain_min.x(), m.domain_min.y(),
                  m.domain_max.x(), m.domain_max.y(), m.cell_size));
  add(s, "algorithms",
      fmt::format("{} {} {} (PIC share {}) smoothing {}, exit {}", to_string(m.shape_function),
                  to_string(m.update_scheme), to_string(m.velocity_transfer), m.pic_fraction,
                  to_string(m.volumetric_smoothing),
                  name_of(particle_exit_names, m.particle_exit)));
  add(s, "boundaries", fmt::format("{}; μ {}", table_line(m.boundaries), m.friction_coefficient));
  add(s, "damping", fmt::format("local {}", m.local_damping));
  if (m.undrained_pore_pressure) {
    add(s, "pore_water", fmt::format("undrained, K_f {}", m.water_bulk_modulus));
  }
  if (m.reservoir_level) {
    add(s, "reservoir",
        fmt::format("level {} m, ρ_w {}, x {} to {} m", *m.reservoir_level, m.water_density,
                    m.reservoir_x_min, m.reservoir_x_max));
  }
  add(s, "time_step", fmt::format("fixed {} s, C {}", m.time_step, m.courant));
  add(s, "rest", fmt::format("KE/PE0 < {} for {} s", m.rest_threshold, m.rest_duration));
  if (pure_mpm) {
    add(s, "mesh", mesh_line(c.mesh, c.file));
    add(s, "start",
        fmt::format("{}×{} per cell, {} initial stress, gravity stage {} s at α {}", m.particles_x,
                    m.particles_y, name_of(initial_stress_names, m.initial_stress),
                    m.gravity_stage_duration, m.gravity_stage_damping));
    add(s, "motion", motion_line(c.fem.motion));
  }
  return s;
}

std::vector<std::string> fingerprint_parts(const SolverSettings& fingerprint) {
  std::vector<std::string> parts;
  for (const auto& [key, value] : fingerprint) parts.push_back(key.substr(prefix.size()));
  return parts;
}

void check_unchanged(const SolverSettings& recorded, const SolverSettings& now,
                     const std::vector<std::string>& allowed, const std::string& source,
                     const Logger& log) {
  const auto names = fingerprint_parts(now);
  for (const std::string& part : allowed) {
    if (std::find(names.begin(), names.end(), part) == names.end()) {
      throw Error("--allow-changed {}: not a part of the case a restart checks (one of: {})", part,
                  fmt::join(names, ", "));
    }
  }
  bool any = false;
  for (const auto& [key, value] : now) {
    const auto found = recorded.find(key);
    if (found == recorded.end()) continue;
    any = true;
    if (found->second == value) continue;
    const std::string part = key.substr(prefix.size());
    const auto shown = [](const SettingValue& v) {
      const auto* text = std::get_if<std::string>(&v);
      return text ? *text : std::string("?");
    };
    if (std::find(allowed.begin(), allowed.end(), part) != allowed.end()) {
      log.warning("{}: the case's {} changed since the checkpoint (--allow-changed {}): {} → {}",
                  source, part, part, shown(found->second), shown(value));
      continue;
    }
    throw Error(
        "{}: the case's {} changed since the checkpoint was written ({} → {}): a restart "
        "continues the same run (--allow-changed {} to continue with the new one)",
        source, part, shown(found->second), shown(value), part);
  }
  if (!any) {
    log.warning("{}: written before checkpoints recorded the case: a changed case goes unnoticed",
                source);
  }
}

}  // namespace slide
