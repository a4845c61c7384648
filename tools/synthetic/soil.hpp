// The soil of the cases (docs/method.md §7), built by hand for the tests of every stage and
// the benchmarks (tools/synthetic: inputs made in code, which both may use; the tests'
// own helpers are in tests/support/).
#pragma once

#include <string>
#include <utility>

#include "common/physics/material.hpp"
#include "common/physics/pm4sand.hpp"

namespace slide::synthetic {

/// A material in one line: its name and model, ρ (kg/m³), E (Pa), ν, and the strength φ
/// (degrees), c (Pa), ψ (degrees); no tension cut-off.
inline Material material(std::string name, MaterialModel model, double density,
                         double youngs_modulus, double poisson_ratio, double friction_angle = 0.0,
                         double cohesion = 0.0, double dilation_angle = 0.0) {
  Material m;
  m.name = std::move(name);
  m.model = model;
  m.density = density;
  m.youngs_modulus = youngs_modulus;
  m.poisson_ratio = poisson_ratio;
  m.friction_angle = friction_angle;
  m.cohesion = cohesion;
  m.dilation_angle = dilation_angle;
  return m;
}

/// column-short's soil: ρ = 1700 kg/m³ unless given, E = 23.8 MPa, ν = 0.23, φ = 22.2°,
/// c = 1 kPa, ψ = 0, the tension cut-off at the Mohr–Coulomb apex (the case-file default).
inline Material soil(MaterialModel model = MaterialModel::linear_elastic, double density = 1700.0) {
  Material m = material("soil", model, density, 23.8e6, 0.23, 22.2, 1000.0);
  m.tension_cutoff = m.apex_stress();
  return m;
}

/// A PM4Sand sand of relative density D_R and contraction rate h_po, every other
/// parameter at its default (G₀ from D_R, ν = 0.3), ρ = 2000 kg/m³; E is the elastic
/// stage's 2(1 + ν) G₀ p_A, as the case reader sets it.
inline Material sand(double relative_density, double contraction_rate) {
  Material m = material("sand", MaterialModel::pm4sand, 2000.0, 1.0, 0.3);
  m.pm4sand.relative_density = relative_density;
  m.pm4sand.contraction_rate = contraction_rate;
  m.youngs_modulus = pm4sand::elastic_stage_youngs_modulus(m);
  return m;
}

}  // namespace slide::synthetic
