// Small builders shared by the mpm tests: materials, grid settings and particle blocks.
#pragma once

#include <cmath>

#include "common/material.hpp"
#include "mpm/mpm_solver.hpp"
#include "mpm/particle_generation.hpp"

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

inline Material frictional_soil() {
  Material m = elastic_soil();
  m.model = MaterialModel::mohr_coulomb;
  m.friction_angle = 22.2;
  m.cohesion = 1000.0;
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

}  // namespace slide::mpm::testing
