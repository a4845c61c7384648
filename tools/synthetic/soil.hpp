// The soil of the cases (docs/method.md §7), built by hand for the tests of every stage and
// the benchmarks (tools/synthetic: inputs made in code, which both may use; the tests'
// own helpers are in tests/support/).
#pragma once

#include "common/physics/material.hpp"

namespace slide::synthetic {

/// column-short's soil: ρ = 1700 kg/m³ unless given, E = 23.8 MPa, ν = 0.23, φ = 22.2°,
/// c = 1 kPa, ψ = 0, the tension cut-off at the Mohr–Coulomb apex (the case-file default).
inline Material soil(MaterialModel model = MaterialModel::linear_elastic, double density = 1700.0) {
  Material m;
  m.name = "soil";
  m.model = model;
  m.density = density;
  m.youngs_modulus = 23.8e6;
  m.poisson_ratio = 0.23;
  m.friction_angle = 22.2;
  m.cohesion = 1000.0;
  m.dilation_angle = 0.0;
  m.tension_cutoff = m.apex_stress();
  return m;
}

}  // namespace slide::synthetic
