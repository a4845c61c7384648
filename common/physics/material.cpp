#include "common/physics/material.hpp"

#include <cmath>
#include <limits>
#include <numbers>
#include <utility>

#include "common/base/error.hpp"
#include "common/base/names.hpp"

namespace slide {

namespace {

constexpr std::array<Named<MaterialModel>, 3> material_model_names{{
    {"linear-elastic", MaterialModel::linear_elastic},
    {"mohr-coulomb", MaterialModel::mohr_coulomb},
    {"pressure-independent-multi-yield", MaterialModel::pressure_independent_multi_yield},
}};

}  // namespace

std::string_view to_string(MaterialModel model) {
  return name_of(material_model_names, model);
}

bool has_strength(MaterialModel model) {
  return model != MaterialModel::linear_elastic;
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
