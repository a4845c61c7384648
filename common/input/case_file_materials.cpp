// The case reader's [[materials]] tables: names, models and their parameters.
// Section, the ranges and the shared readers are in case_file_reader.hpp.
#include "common/input/case_file_reader.hpp"

namespace slide::case_reader {

namespace {

/// Material::validate owns the admissible ranges; its message names `path` and the key
/// ("materials[0]: density = -1 is not admissible (...)"). Rewrite it in the case-file
/// form, at the line of the offending key.
void validate_material(const Material& material, const Section& s) {
  try {
    material.validate(s.path());
  } catch (const Error& error) {
    const std::string_view message = error.what();
    const std::string prefix = s.path() + ": ";
    if (!message.starts_with(prefix)) throw Error("{}: {}", s.where(), message);
    const std::string_view rest = message.substr(prefix.size());
    const std::string key(rest.substr(0, rest.find(' ')));
    throw Error("{}: {}.{}", s.where(key), s.path(), rest);
  }
}

/// A porous material (docs/method.md §10): porosity, and the hydraulic conductivity as
/// `conductivity` or as `conductivity_x` and `conductivity_y`.
void read_pore_water(const Section& s, Material& m) {
  const std::array<std::string_view, 3> flow{"conductivity", "conductivity_x", "conductivity_y"};
  m.porosity = s.number("porosity", any_number(), 0.0);
  if (!s.has("porosity")) {
    for (std::string_view key : flow) s.reject(key, "only used with porosity (a porous material)");
    return;
  }
  if (s.has("conductivity")) {
    for (std::string_view key : {flow[1], flow[2]}) {
      s.reject(key,
               fmt::format("give either {} or its x and y components", s.dotted("conductivity")));
    }
    m.conductivity_x = m.conductivity_y = s.number("conductivity", any_number());
  } else if (s.has("conductivity_x") || s.has("conductivity_y")) {
    m.conductivity_x = s.number("conductivity_x", any_number());
    m.conductivity_y = s.number("conductivity_y", any_number());
  } else {
    s.missing("conductivity");
  }
}

MaterialModel read_model(const Section& s, std::string_view key) {
  return parse_material_model(s.string(key), fmt::format("{}: {}", s.where(key), s.dotted(key)));
}

Material read_material(const Section& s) {
  Material m;
  m.name = s.string("name");
  if (m.name.empty()) s.fail("name", "a material needs a non-empty name");
  // `model` serves both phases; `fem_model` and `mpm_model` name a phase's own model
  // (the reference workflow: pressure-independent multi-yield in FE, Mohr–Coulomb in MPM).
  if (s.has("model") && s.has("fem_model")) {
    s.fail("fem_model", "give either model (both phases) or fem_model, not both");
  }
  m.model = read_model(s, s.has("fem_model") ? "fem_model" : "model");
  if (s.has("mpm_model")) m.mpm_model = read_model(s, "mpm_model");
  // Only finiteness here: the ranges are Material::validate's.
  m.density = s.number("density", any_number());
  m.youngs_modulus = s.number("youngs_modulus", any_number());
  m.poisson_ratio = s.number("poisson_ratio", any_number());
  const bool mohr_coulomb = m.uses(MaterialModel::mohr_coulomb);
  const bool multi_yield = m.uses(MaterialModel::pressure_independent_multi_yield);
  if (!mohr_coulomb && !multi_yield) {
    for (std::string_view key :
         {"friction_angle", "cohesion", "dilation_angle", "tension_cutoff"}) {
      s.reject(key, "not used by model \"linear-elastic\" (remove it, or use \"mohr-coulomb\")");
    }
  } else {
    m.friction_angle = s.number("friction_angle", any_number());
    m.cohesion = s.number("cohesion", any_number());
  }
  if (mohr_coulomb) {
    m.dilation_angle = s.number("dilation_angle", any_number(), 0.0);
  } else if (multi_yield) {
    for (std::string_view key : {"dilation_angle", "tension_cutoff"}) {
      s.reject(key,
               "not used by model \"pressure-independent-multi-yield\" (no dilation, no tension "
               "cut-off)");
    }
  }
  // Read whatever the models: a user switching fem_model back and forth keeps them.
  m.peak_shear_strain = s.number("peak_shear_strain", any_number(), m.peak_shear_strain);
  m.yield_surfaces = s.integer("yield_surfaces", 1, max_yield_surfaces, m.yield_surfaces);
  // The default cut-off is the apex c·cot φ (infinite for φ = 0); +inf may be written.
  const Range cutoff{.min = -infinity, .max = infinity, .max_closed = true};
  m.tension_cutoff = s.number("tension_cutoff", cutoff, m.apex_stress());
  read_pore_water(s, m);
  validate_material(m, s);
  return m;
}

}  // namespace

MaterialTable read_materials(const Section& root) {
  if (!root.has("materials")) root.missing("materials");
  if (root.node("materials").is_table()) {
    root.fail("materials", "expected an array of tables ([[materials]]), found a table");
  }
  const Section::Keys keys{"name",           "model",          "fem_model",
                           "mpm_model",      "density",        "youngs_modulus",
                           "poisson_ratio",  "friction_angle", "cohesion",
                           "dilation_angle", "tension_cutoff", "peak_shear_strain",
                           "yield_surfaces", "porosity",       "conductivity",
                           "conductivity_x", "conductivity_y"};
  MaterialTable materials;
  for (const Section& s : root.tables("materials", keys)) {
    Material material = read_material(s);
    for (const Material& other : materials) {
      if (other.name == material.name) {
        s.fail("name", fmt::format("\"{}\" is defined twice (material names must be unique)",
                                   material.name));
      }
    }
    materials.push_back(std::move(material));
  }
  if (materials.empty()) root.fail("materials", "at least one [[materials]] table is required");
  return materials;
}

/// A material reference: the name must be one of the case's materials.
std::string read_material_name(const Section& s, std::string_view key,
                               const MaterialTable& materials) {
  std::string name = s.string(key);
  const bool known = std::any_of(materials.begin(), materials.end(),
                                 [&](const Material& m) { return m.name == name; });
  if (!known) {
    std::vector<std::string_view> names;
    for (const Material& m : materials) names.push_back(m.name);
    s.fail(key, fmt::format("no material called \"{}\" (the case defines: {})", name, join(names)));
  }
  return name;
}

}  // namespace slide::case_reader
