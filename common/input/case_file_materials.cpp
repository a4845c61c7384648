// The case reader's [[materials]] tables: names, models and their parameters.
// Section, the ranges and the shared readers are in case_file_reader.hpp.
#include "common/input/case_file_reader.hpp"
#include "common/physics/element_test.hpp"
#include "common/physics/pm4sand.hpp"

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

/// PM4Sand's secondary parameters: the keys of [materials.pm4sand] and their members.
constexpr std::array<std::pair<std::string_view, double Pm4SandParameters::*>, 18>
    pm4sand_secondary{{
        {"atmospheric_pressure", &Pm4SandParameters::atmospheric_pressure},
        {"h0", &Pm4SandParameters::h0},
        {"e_max", &Pm4SandParameters::e_max},
        {"e_min", &Pm4SandParameters::e_min},
        {"n_b", &Pm4SandParameters::n_b},
        {"n_d", &Pm4SandParameters::n_d},
        {"a_do", &Pm4SandParameters::a_do},
        {"z_max", &Pm4SandParameters::z_max},
        {"c_z", &Pm4SandParameters::c_z},
        {"c_e", &Pm4SandParameters::c_e},
        {"critical_friction_angle", &Pm4SandParameters::critical_friction_angle},
        {"c_gd", &Pm4SandParameters::c_gd},
        {"c_dr", &Pm4SandParameters::c_dr},
        {"c_kaf", &Pm4SandParameters::c_kaf},
        {"q", &Pm4SandParameters::q},
        {"r", &Pm4SandParameters::r},
        {"m", &Pm4SandParameters::m},
        {"strain_step", &Pm4SandParameters::strain_step},
    }};

/// h_po from the element test: undrained cyclic simple shear reaches 3 % strain in 15
/// cycles at CSR = `target_crr` (default: Idriss–Boulanger 2008 at (N1)60cs = 46 D_R²).
void calibrate_pm4sand(const Section& s, const Section& material, Material& m) {
  Pm4SandParameters& p = m.pm4sand;
  // Check the other parameters first: the calibration runs the model.
  p.contraction_rate = 1.0;
  validate_material(m, material);
  const double crr = s.number("target_crr", Range{.min = 0.0, .max = 2.0, .unit = {}, .note = {}},
                              element_test::default_target_crr(p.relative_density));
  try {
    const auto result = element_test::calibrate_contraction_rate(m, crr);
    p.contraction_rate = result.contraction_rate;
    p.calibrated_crr = crr;
    p.calibrated_cycles = result.cycles;
  } catch (const Error& error) {
    s.fail("calibrate_to_crr", error.what());
  }
}

/// PM4Sand's [materials.pm4sand] table: D_R, and G₀ and h_po or their derivations
/// (docs/method.md §10), the secondary parameters' overrides; E of the elastic stage.
void read_pm4sand(const Section& material, Material& m) {
  Section::Keys keys{
      "relative_density", "blow_count",       "shear_wave_speed", "shear_modulus_coefficient",
      "contraction_rate", "calibrate_to_crr", "target_crr"};
  for (const auto& entry : pm4sand_secondary) keys.push_back(entry.first);
  const Section s = material.table("pm4sand", keys);
  Pm4SandParameters& p = m.pm4sand;
  // D_R, or (N1)60 with D_R = sqrt((N1)60/46) (the report's field correlation).
  if (s.has("relative_density") == s.has("blow_count")) {
    s.fail("relative_density", "give either relative_density (D_R) or blow_count ((N1)60)");
  }
  p.relative_density =
      s.has("blow_count")
          ? pm4sand::relative_density_of(
                s.number("blow_count", Range{.min = 0.0, .max = 200.0, .unit = {}, .note = {}}))
          : s.number("relative_density", any_number());
  p.shear_modulus_coefficient =
      s.number("shear_modulus_coefficient", any_number(), Pm4SandParameters::derived);
  for (const auto& [key, member] : pm4sand_secondary) {
    p.*member = s.number(key, any_number(), p.*member);
  }
  if (s.has("shear_wave_speed")) {  // V_s1 instead of G₀
    s.reject("shear_modulus_coefficient",
             "give either shear_modulus_coefficient or shear_wave_speed");
    const double vs1 = s.number("shear_wave_speed", positive("m/s"));
    p.shear_modulus_coefficient =
        pm4sand::shear_modulus_coefficient_from_wave_speed(m.density, vs1, p.atmospheric_pressure);
  }
  m.youngs_modulus = pm4sand::elastic_stage_youngs_modulus(m);
  const bool calibrate = s.boolean("calibrate_to_crr", false);
  if (calibrate == s.has("contraction_rate")) {
    s.fail("contraction_rate", "give either contraction_rate (h_po) or calibrate_to_crr = true");
  }
  if (calibrate) {
    calibrate_pm4sand(s, material, m);
  } else {
    s.reject("target_crr", "only used with calibrate_to_crr = true");
    p.contraction_rate = s.number("contraction_rate", any_number());
  }
}

/// A material that may liquefy ([materials.liquefaction], docs/method.md §10): the rule
/// that marks its particles liquefied at the transfer, and their residual strength, with
/// the blow count and φ′ of the cap resolved (PM4Sand: 46 D_R² and φ_cv by default).
void read_liquefaction(const Section& material, Material& m) {
  if (!material.has("liquefaction")) return;
  const Section s = material.table(
      "liquefaction",
      Section::Keys{"pore_pressure_ratio", "shear_strain", "correlation", "blow_count",
                    "strength_ratio", "friction_angle", "minimum_strength", "peak_strength_ratio",
                    "softening_strain", "shear_modulus_ratio", "poisson_ratio"});
  LiquefactionParameters& q = m.liquefaction;
  q.enabled = true;
  constexpr double unset = LiquefactionParameters::unset;
  // Only the criteria given: a table with shear_strain alone has no r_u criterion.
  const bool by_strain = s.has("shear_strain");
  q.pore_pressure_ratio =
      s.number("pore_pressure_ratio", any_number(), by_strain ? unset : q.pore_pressure_ratio);
  q.shear_strain = s.number("shear_strain", any_number(), unset);
  if (s.has("correlation")) {
    q.correlation = parse_residual_strength_correlation(
        s.string("correlation"),
        fmt::format("{}: {}", s.where("correlation"), s.dotted("correlation")));
  }
  using C = ResidualStrengthCorrelation;
  const bool needs_blow_count = q.correlation != C::ratio && q.correlation != C::none;
  const bool pm4sand = m.model == MaterialModel::pm4sand;
  if (needs_blow_count) {
    if (!s.has("blow_count") && !pm4sand) s.missing("blow_count");
    q.blow_count =
        s.number("blow_count", any_number(),
                 pm4sand ? 46.0 * m.pm4sand.relative_density * m.pm4sand.relative_density : unset);
  } else {
    s.reject("blow_count", "only used by a correlation of the blow count");
  }
  if (q.correlation == C::ratio) {
    q.strength_ratio = s.number("strength_ratio", any_number());
  } else {
    s.reject("strength_ratio", "only used with correlation = \"ratio\"");
  }
  const double own_angle = pm4sand ? m.pm4sand.critical_friction_angle : m.friction_angle;
  q.friction_angle = s.number("friction_angle", any_number(), own_angle > 0.0 ? own_angle : unset);
  if (std::isnan(q.friction_angle) && q.correlation != C::none) s.missing("friction_angle");
  q.minimum_strength = s.number("minimum_strength", any_number(), q.minimum_strength);
  q.peak_strength_ratio = s.number("peak_strength_ratio", any_number(), unset);
  q.softening_strain = s.number("softening_strain", any_number(), unset);
  q.shear_modulus_ratio = s.number("shear_modulus_ratio", any_number(), q.shear_modulus_ratio);
  q.poisson_ratio = s.number("poisson_ratio", any_number(), q.poisson_ratio);
}

/// ν, and E or (PM4Sand) the model's parameters, from which E follows.
void read_elasticity(const Section& s, Material& m) {
  m.poisson_ratio = s.number("poisson_ratio", any_number(), 0.3);
  if (m.uses(MaterialModel::pm4sand)) {
    // The elastic (geostatic) stage of PM4Sand has G = G₀ p_A (the reference
    // implementations' elastic stage): E follows.
    s.reject("youngs_modulus",
             "not used with model \"pm4sand\" (its elastic stage has G = G₀ p_A)");
    read_pm4sand(s, m);
    return;
  }
  s.reject("pm4sand", "only used with model \"pm4sand\"");
  m.youngs_modulus = s.number("youngs_modulus", any_number());
  if (!s.has("poisson_ratio")) s.missing("poisson_ratio");
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
  read_elasticity(s, m);
  const bool mohr_coulomb = m.uses(MaterialModel::mohr_coulomb);
  const bool multi_yield = m.uses(MaterialModel::pressure_independent_multi_yield);
  if (!mohr_coulomb && !multi_yield) {
    for (std::string_view key :
         {"friction_angle", "cohesion", "dilation_angle", "tension_cutoff"}) {
      s.reject(key, fmt::format("not used by model \"{}\" (remove it, or use \"mohr-coulomb\")",
                                to_string(m.model)));
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
  read_liquefaction(s, m);
  validate_material(m, s);
  return m;
}

}  // namespace

MaterialTable read_materials(const Section& root) {
  if (!root.has("materials")) root.missing("materials");
  if (root.node("materials").is_table()) {
    root.fail("materials", "expected an array of tables ([[materials]]), found a table");
  }
  const Section::Keys keys{
      "name",           "model",          "fem_model",      "mpm_model",
      "density",        "youngs_modulus", "poisson_ratio",  "friction_angle",
      "cohesion",       "dilation_angle", "tension_cutoff", "peak_shear_strain",
      "yield_surfaces", "porosity",       "conductivity",   "conductivity_x",
      "conductivity_y", "pm4sand",        "liquefaction"};
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
