#include "transfer/transfer_report.hpp"

#include <cmath>

#include <fmt/format.h>

namespace slide::transfer {

namespace {

double relative_difference(double after, double before) {
  const double scale = std::max(std::abs(before), std::abs(after));
  return scale > 0.0 ? (after - before) / scale : 0.0;
}

std::string json_string(std::string_view text) {
  std::string out = "\"";
  for (const char ch : text) {
    switch (ch) {
      case '"':
        out += "\\\"";
        break;
      case '\\':
        out += "\\\\";
        break;
      case '\n':
        out += "\\n";
        break;
      case '\t':
        out += "\\t";
        break;
      default:
        if (static_cast<unsigned char>(ch) < 0x20) {
          out += fmt::format("\\u{:04x}", static_cast<int>(ch));
        } else {
          out += ch;
        }
    }
  }
  return out + "\"";
}

/// Shortest representation that reads back to the same double; JSON has no NaN or ∞.
std::string json_number(double value) {
  return std::isfinite(value) ? fmt::format("{}", value) : std::string("null");
}

std::string json_vector(const Vec2& v) {
  return fmt::format("[{}, {}]", json_number(v.x()), json_number(v.y()));
}

}  // namespace

/// The saturated soil's lines: pore pressure carried, liquefied particles per material.
void add_pore_water_lines(const PoreWaterReport& w, std::vector<std::string>& lines) {
  if (!w.saturated) return;
  lines.push_back(fmt::format(
      "pore water: {} saturated particles, ∫p dA FE {:.9e} N/m, particles {:.9e} N/m "
      "(relative {:+.2e}); largest r_u,max {:.3f}; {} particle(s) with Δp capped at σ′v0",
      w.saturated_particles, w.pore_force_fe, w.pore_force_particles,
      relative_difference(w.pore_force_particles, w.pore_force_fe), w.max_pore_pressure_ratio,
      w.capped_excess));
  for (const auto& m : w.materials) {
    lines.push_back(fmt::format(
        "liquefied {}: {} of {} particles ({:.1f} m2) by {}; S_r {} from {:.3g} to {:.3g} kPa",
        m.name, m.liquefied, m.particles, m.liquefied_area, m.rule, m.correlation,
        m.residual_strength_min / 1e3, m.residual_strength_max / 1e3));
  }
}

std::vector<std::string> format_report_lines(const TransferReport& r) {
  std::vector<std::string> lines;
  lines.push_back(fmt::format(
      "transfer at t = {} s: {} {} elements, {} Gauss points -> {} particles ({} per element: {})",
      r.time, r.elements, r.element_type, r.gauss_points, r.particles, r.particles_per_element,
      r.particle_rule));
  if (r.stress_interpolation == "element") {
    lines.push_back("Gauss-point fields: element (the owning element's nearest Gauss point)");
  } else {
    std::string how =
        fmt::format("Gauss-point fields: {}, multiquadric c = {:.6g} m, polynomial {}",
                    r.stress_interpolation, r.rbf_shape, r.rbf_polynomial);
    if (r.rbf_neighbours > 0) how += fmt::format(", k = {}", r.rbf_neighbours);
    lines.push_back(how);
    lines.push_back(fmt::format(
        "  condition estimate {:.3e} ({} factorisation{}), residual at the Gauss points: "
        "stress max {:.3e} Pa, rms {:.3e} Pa, relative max {:.3e}",
        r.condition_estimate, r.factorisations, r.factorisations == 1 ? "" : "s",
        r.residual_stress_max, r.residual_stress_rms, r.residual_relative_max));
    if (r.reduced_polynomial > 0) {
      lines.push_back(
          fmt::format("  {} neighbourhood(s) with collinear Gauss points: linear polynomial "
                      "reduced to a constant",
                      r.reduced_polynomial));
    }
  }
  lines.push_back(fmt::format("mass     FE {:.9e} kg/m, particles {:.9e} kg/m (relative {:+.2e})",
                              r.mass_fe, r.mass_particles,
                              relative_difference(r.mass_particles, r.mass_fe)));
  lines.push_back(fmt::format("volume   FE {:.9e} m3/m, particles {:.9e} m3/m (relative {:+.2e})",
                              r.volume_fe, r.volume_particles,
                              relative_difference(r.volume_particles, r.volume_fe)));
  lines.push_back(
      fmt::format("momentum FE nodal ({:.6e}, {:.6e}), FE element ({:.6e}, {:.6e}), particles "
                  "({:.6e}, {:.6e}) kg m/s per m",
                  r.momentum_fe_nodal.x(), r.momentum_fe_nodal.y(), r.momentum_fe_element.x(),
                  r.momentum_fe_element.y(), r.momentum_particles.x(), r.momentum_particles.y()));
  lines.push_back(fmt::format(
      "kinetic energy FE nodal {:.6e}, FE element {:.6e}, particles {:.6e} J/m",
      r.kinetic_energy_fe_nodal, r.kinetic_energy_fe_element, r.kinetic_energy_particles));
  if (!r.inverted_elements.empty()) {
    std::string ids;
    for (std::size_t i = 0; i < r.inverted_elements.size() && i < 20; ++i) {
      ids += fmt::format("{}{}", i == 0 ? "" : " ", r.inverted_elements[i]);
    }
    if (r.inverted_elements.size() > 20) ids += " …";
    lines.push_back(fmt::format(
        "{} inverted element(s) transferred with their reference volume (--allow-inverted): {}",
        r.inverted_elements.size(), ids));
  }
  if (r.excluded_gauss_points > 0) {
    lines.push_back(fmt::format(
        "{} collapsed element(s) (inverted or V_t/V_0 < {:g}): their {} Gauss point(s) are not "
        "RBF centres",
        r.collapsed_elements, r.collapsed_volume_ratio, r.excluded_gauss_points));
  }
  if (r.limited_particles > 0) {
    lines.push_back(fmt::format(
        "{} particle(s) with an RBF overshoot limited to the range of their element patch "
        "({} in a stress component)",
        r.limited_particles, r.limited_stress_particles));
  }
  if (r.clamped_plastic_strain > 0) {
    lines.push_back(
        fmt::format("{} particle(s) with a negative interpolated plastic shear strain set to 0",
                    r.clamped_plastic_strain));
  }
  add_pore_water_lines(r.pore_water, lines);
  lines.push_back(fmt::format("time {:.3f} s (interpolation {:.3f} s)", r.seconds_total,
                              r.seconds_interpolation));
  return lines;
}

std::vector<std::string> report_warnings(const TransferReport& report) {
  std::vector<std::string> lines;
  if (!report.inverted_elements.empty()) {
    lines.push_back(
        fmt::format("{} inverted element(s) transferred with their reference volume, first {}",
                    report.inverted_elements.size(), report.inverted_elements.front()));
  }
  if (report.excluded_gauss_points > 0) {
    lines.push_back(fmt::format(
        "{} collapsed element(s) (inverted or V_t/V_0 < {:g}) left out of the RBF centres; "
        "their particles take the fields interpolated from the other elements",
        report.collapsed_elements, report.collapsed_volume_ratio));
  }
  if (report.limited_stress_particles > 0) {
    lines.push_back(
        fmt::format("{} particle(s) had RBF stresses beyond their element patch's range, limited "
                    "to it (crowded or folded Gauss points; compare --stress-interpolation "
                    "element)",
                    report.limited_stress_particles));
  }
  return lines;
}

/// The saturated soil's members of the report's JSON object, through `field`.
template <class Field>
void add_pore_water_json(const PoreWaterReport& w, Field& field) {
  std::string materials = "[";
  for (std::size_t i = 0; i < w.materials.size(); ++i) {
    const auto& m = w.materials[i];
    materials += fmt::format(
        "{}{{\"name\": {}, \"rule\": {}, \"correlation\": {}, \"particles\": {}, "
        "\"liquefied\": {}, \"liquefied_area\": {}, \"residual_strength_min\": {}, "
        "\"residual_strength_max\": {}}}",
        i == 0 ? "" : ", ", json_string(m.name), json_string(m.rule), json_string(m.correlation),
        m.particles, m.liquefied, json_number(m.liquefied_area),
        json_number(m.residual_strength_min), json_number(m.residual_strength_max));
  }
  materials += "]";
  field("saturated_particles", fmt::format("{}", w.saturated_particles));
  field("pore_force_fe", json_number(w.pore_force_fe));
  field("pore_force_particles", json_number(w.pore_force_particles));
  field("max_pore_pressure_ratio", json_number(w.max_pore_pressure_ratio));
  field("capped_excess_pore_pressure", fmt::format("{}", w.capped_excess));
  field("liquefaction", materials);
}

std::string report_json(const TransferReport& r) {
  std::string inverted = "[";
  for (std::size_t i = 0; i < r.inverted_elements.size(); ++i) {
    inverted += fmt::format("{}{}", i == 0 ? "" : ", ", r.inverted_elements[i]);
  }
  inverted += "]";
  std::string json = "{\n";
  auto field = [&json](std::string_view name, const std::string& value, bool last = false) {
    json += fmt::format("  \"{}\": {}{}\n", name, value, last ? "" : ",");
  };
  field("input", json_string(r.input));
  field("output", json_string(r.output));
  field("case", json_string(r.case_name));
  field("time", json_number(r.time));
  field("element_type", json_string(r.element_type));
  field("elements", fmt::format("{}", r.elements));
  field("gauss_points", fmt::format("{}", r.gauss_points));
  field("particles", fmt::format("{}", r.particles));
  field("particles_per_element", json_string(r.particles_per_element));
  field("particle_rule", json_string(r.particle_rule));
  field("stress_interpolation", json_string(r.stress_interpolation));
  field("rbf_polynomial", json_string(r.rbf_polynomial));
  field("rbf_shape", json_number(r.rbf_shape));
  field("rbf_neighbours", fmt::format("{}", r.rbf_neighbours));
  field("condition_estimate", json_number(r.condition_estimate));
  field("factorisations", fmt::format("{}", r.factorisations));
  field("reduced_polynomial", fmt::format("{}", r.reduced_polynomial));
  field("residual_stress_max", json_number(r.residual_stress_max));
  field("residual_stress_rms", json_number(r.residual_stress_rms));
  field("residual_relative_max", json_number(r.residual_relative_max));
  field("mass_fe", json_number(r.mass_fe));
  field("mass_particles", json_number(r.mass_particles));
  field("volume_fe", json_number(r.volume_fe));
  field("volume_particles", json_number(r.volume_particles));
  field("momentum_fe_nodal", json_vector(r.momentum_fe_nodal));
  field("momentum_fe_element", json_vector(r.momentum_fe_element));
  field("momentum_particles", json_vector(r.momentum_particles));
  field("kinetic_energy_fe_nodal", json_number(r.kinetic_energy_fe_nodal));
  field("kinetic_energy_fe_element", json_number(r.kinetic_energy_fe_element));
  field("kinetic_energy_particles", json_number(r.kinetic_energy_particles));
  field("inverted_elements", inverted);
  field("collapsed_volume_ratio", json_number(r.collapsed_volume_ratio));
  field("collapsed_elements", fmt::format("{}", r.collapsed_elements));
  field("excluded_gauss_points", fmt::format("{}", r.excluded_gauss_points));
  field("clamped_plastic_strain", fmt::format("{}", r.clamped_plastic_strain));
  field("limited_particles", fmt::format("{}", r.limited_particles));
  field("limited_stress_particles", fmt::format("{}", r.limited_stress_particles));
  if (r.pore_water.saturated) add_pore_water_json(r.pore_water, field);
  field("seconds_interpolation", json_number(r.seconds_interpolation));
  field("seconds_total", json_number(r.seconds_total), true);
  json += "}\n";
  return json;
}

std::filesystem::path report_path(const std::filesystem::path& particle_file) {
  std::filesystem::path path = particle_file;
  if (path.extension() == ".h5") path.replace_extension();
  path += ".transfer.json";
  return path;
}

}  // namespace slide::transfer
