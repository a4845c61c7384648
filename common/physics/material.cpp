#include "common/physics/material.hpp"

#include <cmath>
#include <limits>
#include <numbers>
#include <utility>

#include "common/base/error.hpp"
#include "common/base/names.hpp"

namespace slide {

namespace {

constexpr std::array<Named<MaterialModel>, 4> material_model_names{{
    {"linear-elastic", MaterialModel::linear_elastic},
    {"mohr-coulomb", MaterialModel::mohr_coulomb},
    {"pressure-independent-multi-yield", MaterialModel::pressure_independent_multi_yield},
    {"pm4sand", MaterialModel::pm4sand},
}};

constexpr std::array<Named<ResidualStrengthCorrelation>, 5> correlation_names{{
    {"idriss-boulanger-void-redistribution",
     ResidualStrengthCorrelation::idriss_boulanger_void_redistribution},
    {"idriss-boulanger", ResidualStrengthCorrelation::idriss_boulanger},
    {"olson-stark", ResidualStrengthCorrelation::olson_stark},
    {"ratio", ResidualStrengthCorrelation::ratio},
    {"none", ResidualStrengthCorrelation::none},
}};

}  // namespace

std::string_view to_string(MaterialModel model) {
  // Liquefied particles' model: a transfer's doing, not a name a case file may give.
  if (model == MaterialModel::residual_strength) return "residual-strength";
  return name_of(material_model_names, model);
}

std::string_view to_string(ResidualStrengthCorrelation correlation) {
  return name_of(correlation_names, correlation);
}

ResidualStrengthCorrelation parse_residual_strength_correlation(std::string_view text,
                                                                std::string_view where) {
  return parse_name(correlation_names, text, where, "residual-strength correlation");
}

bool has_strength(MaterialModel model) {
  return model == MaterialModel::mohr_coulomb ||
         model == MaterialModel::pressure_independent_multi_yield;
}

MaterialModel parse_material_model(std::string_view text, std::string_view where) {
  return parse_name(material_model_names, text, where, "material model");
}

double Material::lame_lambda() const {
  return youngs_modulus * poisson_ratio / ((1.0 + poisson_ratio) * (1.0 - 2.0 * poisson_ratio));
}

double Material::p_wave_modulus() const {
  return lame_lambda() + 2.0 * shear_modulus();
}

double Material::p_wave_speed() const {
  return std::sqrt(p_wave_modulus() / density);
}

double Material::apex_stress() const {
  const double phi = friction_angle * std::numbers::pi / 180.0;
  if (phi <= 0.0) return std::numeric_limits<double>::infinity();
  return cohesion / std::tan(phi);
}

void Material::validate_pm4sand(std::string_view where) const {
  const Pm4SandParameters& p = pm4sand;
  auto require = [&](bool ok, std::string_view key, double value, std::string_view expected) {
    if (!ok) throw Error("{}: pm4sand.{} = {} is not admissible ({})", where, key, value, expected);
  };
  // A derived (NaN) secondary parameter passes; a given one must be in range.
  auto given_in = [](double v, double lo, double hi) {
    return std::isnan(v) || (std::isfinite(v) && v > lo && v < hi);
  };
  const double dr = p.relative_density;
  require(std::isfinite(dr) && dr >= 0.1 && dr <= 1.0, "relative_density", dr,
          "expected 0.1 ≤ D_R ≤ 1 (the model is calibrated for D_R from 0.35 to 0.75)");
  require(given_in(p.shear_modulus_coefficient, 0.0, 1e5), "shear_modulus_coefficient",
          p.shear_modulus_coefficient, "expected 0 < G₀ < 1e5 (typically 300 to 1500)");
  require(std::isfinite(p.contraction_rate) && p.contraction_rate > 0.0 && p.contraction_rate < 1e3,
          "contraction_rate", p.contraction_rate,
          "expected 0 < h_po < 1000 (typically 0.05 to 2; or calibrate_to_crr = true)");
  require(std::isfinite(p.atmospheric_pressure) && p.atmospheric_pressure > 0.0,
          "atmospheric_pressure", p.atmospheric_pressure, "expected p_A > 0 Pa");
  require(given_in(p.h0, 0.0, 100.0), "h0", p.h0, "expected 0 < h0 < 100");
  require(std::isfinite(p.e_min) && std::isfinite(p.e_max) && p.e_min > 0.0 && p.e_max > p.e_min,
          "e_max", p.e_max, "expected 0 < e_min < e_max");
  require(std::isfinite(p.n_b) && p.n_b >= 0.0, "n_b", p.n_b, "expected n_b ≥ 0");
  require(std::isfinite(p.n_d) && p.n_d >= 0.0, "n_d", p.n_d, "expected n_d ≥ 0");
  require(given_in(p.a_do, 0.0, 100.0), "a_do", p.a_do, "expected 0 < A_do < 100");
  require(given_in(p.z_max, 0.0, 100.0), "z_max", p.z_max, "expected 0 < z_max < 100");
  require(std::isfinite(p.c_z) && p.c_z > 0.0, "c_z", p.c_z, "expected c_z > 0");
  require(given_in(p.c_e, 0.0, 100.0), "c_e", p.c_e, "expected 0 < c_e < 100");
  require(std::isfinite(p.critical_friction_angle) && p.critical_friction_angle > 0.0 &&
              p.critical_friction_angle < 60.0,
          "critical_friction_angle", p.critical_friction_angle, "expected 0 < φ_cv < 60 degrees");
  require(std::isfinite(p.c_gd) && p.c_gd > 0.0, "c_gd", p.c_gd, "expected C_GD > 0");
  require(given_in(p.c_dr, 0.0, 1e3), "c_dr", p.c_dr, "expected C_DR > 0");
  require(given_in(p.c_kaf, 0.0, 1e3), "c_kaf", p.c_kaf, "expected C_kaf > 0");
  require(std::isfinite(p.q) && p.q > std::log(100.0) + 1.0, "q", p.q,
          "expected Q > ln 100 + 1 (the critical state line must stay positive to 1 atm)");
  require(std::isfinite(p.r) && p.r > 0.0, "r", p.r, "expected R > 0");
  require(std::isfinite(p.m) && p.m > 0.0 && p.m < 0.5, "m", p.m, "expected 0 < m < 0.5");
  require(std::isfinite(p.strain_step) && p.strain_step >= 1e-7 && p.strain_step <= 1e-3,
          "strain_step", p.strain_step, "expected 1e-7 ≤ strain step ≤ 1e-3");
}

void Material::validate_liquefaction(std::string_view where) const {
  const LiquefactionParameters& q = liquefaction;
  auto require = [&](bool ok, std::string_view key, double value, std::string_view expected) {
    if (!ok) {
      throw Error("{}: liquefaction.{} = {} is not admissible ({})", where, key, value, expected);
    }
  };
  auto unset_or = [](double v, double lo, double hi) {
    return std::isnan(v) || (std::isfinite(v) && v > lo && v <= hi);
  };
  require(unset_or(q.pore_pressure_ratio, 0.0, 1.0), "pore_pressure_ratio", q.pore_pressure_ratio,
          "expected 0 < r_u ≤ 1");
  require(unset_or(q.shear_strain, 0.0, 10.0), "shear_strain", q.shear_strain,
          "expected 0 < γ ≤ 10 (engineering shear strain; 0.08 is 8 %)");
  require(!std::isnan(q.pore_pressure_ratio) || !std::isnan(q.shear_strain), "pore_pressure_ratio",
          q.pore_pressure_ratio, "the rule needs pore_pressure_ratio or shear_strain");
  require(saturable() || std::isnan(q.pore_pressure_ratio), "pore_pressure_ratio",
          q.pore_pressure_ratio, "a dry material has no pore pressure: give porosity");
  require(unset_or(q.blow_count, -1.0, 60.0), "blow_count", q.blow_count,
          "expected 0 ≤ (N1)60cs-Sr ≤ 60");
  require(unset_or(q.strength_ratio, 0.0, 2.0), "strength_ratio", q.strength_ratio,
          "expected 0 < S_r/σ′v0 ≤ 2");
  require(unset_or(q.friction_angle, 0.0, 89.0), "friction_angle", q.friction_angle,
          "expected 0 < φ′ < 90 degrees");
  require(std::isfinite(q.minimum_strength) && q.minimum_strength >= 0.0, "minimum_strength",
          q.minimum_strength, "expected S_r,min ≥ 0 Pa");
  require(unset_or(q.peak_strength_ratio, 0.0, 2.0), "peak_strength_ratio", q.peak_strength_ratio,
          "expected 0 < S_u,peak/σ′v0 ≤ 2");
  require(std::isnan(q.peak_strength_ratio) == std::isnan(q.softening_strain), "softening_strain",
          q.softening_strain, "softening needs both peak_strength_ratio and softening_strain");
  require(unset_or(q.softening_strain, 0.0, 10.0), "softening_strain", q.softening_strain,
          "expected 0 < γ_s ≤ 10");
  require(std::isfinite(q.shear_modulus_ratio) && q.shear_modulus_ratio > 0.0 &&
              q.shear_modulus_ratio <= 1.0,
          "shear_modulus_ratio", q.shear_modulus_ratio, "expected 0 < G_liq/G ≤ 1");
  require(std::isfinite(q.poisson_ratio) && q.poisson_ratio >= 0.0 && q.poisson_ratio < 0.5,
          "poisson_ratio", q.poisson_ratio, "expected 0 ≤ ν < 0.5 (undrained: close to 0.5)");
}

void Material::validate(std::string_view where) const {
  auto require = [&](bool ok, std::string_view key, double value, std::string_view expected) {
    if (!ok) throw Error("{}: {} = {} is not admissible ({})", where, key, value, expected);
  };
  auto finite = [](double v) { return std::isfinite(v); };
  require(finite(density) && density > 0.0, "density", density, "expected ρ > 0 kg/m³");
  require(finite(youngs_modulus) && youngs_modulus > 0.0, "youngs_modulus", youngs_modulus,
          "expected E > 0 Pa");
  require(finite(poisson_ratio) && poisson_ratio > -1.0 && poisson_ratio < 0.5, "poisson_ratio",
          poisson_ratio, "expected −1 < ν < 0.5");
  if (uses(MaterialModel::pressure_independent_multi_yield)) {
    require(finite(peak_shear_strain) && peak_shear_strain > 0.0, "peak_shear_strain",
            peak_shear_strain, "expected γ_peak > 0");
    require(yield_surfaces >= 1 && yield_surfaces <= max_yield_surfaces, "yield_surfaces",
            yield_surfaces, "expected 1 to 40 surfaces");
  }
  if (uses(MaterialModel::pm4sand)) validate_pm4sand(where);
  if (liquefaction.enabled) validate_liquefaction(where);
  require(finite(porosity) && porosity >= 0.0 && porosity < 1.0, "porosity", porosity,
          "expected 0 ≤ n < 1 (0: dry)");
  if (saturable()) {
    for (const auto& [key, k] : {std::pair{"conductivity_x", conductivity_x},
                                 std::pair{"conductivity_y", conductivity_y}}) {
      require(finite(k) && k >= 0.0 && k <= 1.0, key, k,
              "expected 0 ≤ k ≤ 1 m/s (0: no flow; clean gravel is about 1e-2)");
    }
  }
  if (!has_strength(model) && !has_strength(model_of(Phase::mpm))) return;
  require(finite(friction_angle) && friction_angle >= 0.0 && friction_angle < 90.0,
          "friction_angle", friction_angle, "expected 0 ≤ φ < 90 degrees");
  require(finite(cohesion) && cohesion >= 0.0, "cohesion", cohesion, "expected c ≥ 0 Pa");
  require(finite(dilation_angle) && dilation_angle >= 0.0 && dilation_angle <= friction_angle,
          "dilation_angle", dilation_angle, "expected 0 ≤ ψ ≤ φ");
  require(!std::isnan(tension_cutoff) && tension_cutoff >= 0.0, "tension_cutoff", tension_cutoff,
          "expected T ≥ 0 Pa");
  require(friction_angle > 0.0 || cohesion > 0.0, "cohesion", cohesion,
          "a material with φ = 0 needs c > 0, or it has no strength at all");
}

}  // namespace slide
