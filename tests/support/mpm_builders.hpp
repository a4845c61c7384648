// Small builders shared by the mpm tests: materials, grid settings and particle blocks.
#pragma once

#include <cmath>
#include <limits>
#include <numbers>

#include "common/physics/material.hpp"
#include "mpm/mpm_solver.hpp"
#include "mpm/particle_generation.hpp"
#include "tools/synthetic/soil.hpp"

namespace slide::mpm::testing {

inline Material elastic_soil(double density = 1700.0, double youngs_modulus = 23.8e6,
                             double poisson_ratio = 0.23) {
  Material m;
  m.name = "soil";
  m.model = MaterialModel::linear_elastic;
  m.density = density;
  m.youngs_modulus = youngs_modulus;
  m.poisson_ratio = poisson_ratio;
  return m;
}

/// The case soil in Mohr–Coulomb without a tension cut-off (the Material default, +∞):
/// the soil the mpm tests have always run, not the case-file default at the apex.
inline Material frictional_soil() {
  Material m = slide::synthetic::soil(MaterialModel::mohr_coulomb);
  m.tension_cutoff = std::numeric_limits<double>::infinity();
  return m;
}

/// Settings on a grid over [lower, upper] with cell size h, every edge free, no gravity
/// unless set.
inline MpmSettings settings_on(const Vec2& lower, const Vec2& upper, double h,
                               ShapeFunction shape = ShapeFunction::gimp,
                               UpdateScheme scheme = UpdateScheme::musl) {
  MpmSettings s;
  s.grid = GridGeometry::covering(lower, upper, h);
  s.boundaries = GridBoundaries::from({}, 0.0);
  s.shape_function = shape;
  s.update_scheme = scheme;
  s.gravity = Vec2::Zero();
  return s;
}

inline void set_edge(MpmSettings& s, GridEdge edge, BoundaryCondition condition) {
  s.boundaries.edge[edge].condition = condition;
}

/// A fixed–free elastic bar in uniaxial strain (fixed at x = 0, rollers above and below),
/// L = 25 m on 1 m cells with 2 × 2 particles per cell, started in its first mode
/// v(x, 0) = v0 sin(πx/2L), v0 = 10⁻³ c: ω1 = (π/2L) c, c = sqrt(M/ρ).
struct FirstModeBar {
  MpmSettings settings;
  MaterialTable materials;
  Particles particles;
  double omega = 0.0;  ///< ω1, rad/s
};

inline FirstModeBar first_mode_bar(ShapeFunction shape, UpdateScheme scheme) {
  const double length = 25.0;
  FirstModeBar bar;
  bar.settings = settings_on(Vec2(0, 0), Vec2(32, 1), 1.0, shape, scheme);
  set_edge(bar.settings, edge_left, BoundaryCondition::fixed);
  set_edge(bar.settings, edge_base, BoundaryCondition::roller);
  set_edge(bar.settings, edge_top, BoundaryCondition::roller);
  const Material material = elastic_soil(1000.0, 1.0e7, 0.3);
  bar.materials = {material};
  bar.particles = generate_box_particles(bar.settings.grid, Vec2(0, 0), Vec2(length, 1), 2, 2,
                                         bar.materials, 0);
  const double c = material.p_wave_speed();
  const double k = std::numbers::pi / (2 * length);
  for (std::size_t p = 0; p < bar.particles.count(); ++p) {
    bar.particles.velocity[p] = Vec2(0.001 * c * std::sin(k * bar.particles.coordinates[p].x()), 0);
  }
  bar.omega = k * c;
  return bar;
}

/// A grid over [0, upper] of 1 m cells under gravity g, its base a Coulomb contact of
/// friction coefficient μ, its other edges free: the sliding tests' floor.
inline MpmSettings on_a_frictional_base(const Vec2& upper, double mu, double g) {
  MpmSettings s = settings_on(Vec2(0, 0), upper, 1.0);
  s.gravity = Vec2(0, -g);
  set_edge(s, edge_base, BoundaryCondition::friction);
  s.boundaries.friction_coefficient = mu;
  return s;
}

}  // namespace slide::mpm::testing
