// Verification of the MPM solver against closed-form solutions (METHOD.md §5):
// free fall, the vibrating bar, the sliding block, the geostatic column, conservation.
#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "mpm_test_support.hpp"

namespace slide::mpm {
namespace {

using namespace testing;

// A block under gravity alone: the grid's central difference integrates a constant
// acceleration exactly, x = x0 + ½ g t², whatever the step sequence.
TEST(FreeFall, PositionFollowsHalfGTSquared) {
  for (auto shape : {ShapeFunction::gimp, ShapeFunction::linear}) {
    MpmSettings s = settings_on(Vec2(0, 0), Vec2(10, 30), 1.0, shape);
    s.gravity = Vec2(0.0, -9.81);
    const MaterialTable materials{elastic_soil()};
    Particles p = generate_box_particles(s.grid, Vec2(4, 24), Vec2(6, 26), 2, 2, materials, 0);
    const auto start = p.coordinates;
    MpmSolver solver(s, materials, std::move(p));
    // Uneven steps, as when landing on output times.
    for (int n = 0; n < 700; ++n) solver.step(n % 7 == 3 ? 4e-4 : 1.1e-3);
    const double t = solver.clock().time;
    const double drop = 0.5 * 9.81 * t * t;
    for (std::size_t k = 0; k < solver.particles().count(); ++k) {
      const auto id = static_cast<std::size_t>(solver.particles().id[k]);
      const double fallen = start[id].y() - solver.particles().coordinates[k].y();
      EXPECT_NEAR(fallen / drop, 1.0, 1e-6) << to_string(shape) << " particle " << k;
      EXPECT_NEAR(solver.particles().coordinates[k].x(), start[id].x(), 1e-12);
    }
  }
}

struct BarResult {
  double omega_numerical = 0.0, omega_exact = 0.0;
  double energy_drift = 0.0;
};

// Fixed–free bar in uniaxial strain (rollers above and below), first mode
// v(x, 0) = v0 sin(πx/2L): ω1 = (π/2L) sqrt(M/ρ). The frequency comes from the zero
// crossings of the total momentum; the energy drift compares the mean total energy
// (kinetic + elastic) of the first and the fifth period.
BarResult vibrating_bar(ShapeFunction shape, UpdateScheme scheme) {
  const double length = 25.0;
  MpmSettings s = settings_on(Vec2(0, 0), Vec2(32, 1), 1.0, shape, scheme);
  set_edge(s, edge_left, BoundaryCondition::fixed);
  set_edge(s, edge_base, BoundaryCondition::roller);
  set_edge(s, edge_top, BoundaryCondition::roller);
  const Material material = elastic_soil(1000.0, 1.0e7, 0.3);
  const MaterialTable materials{material};
  Particles p = generate_box_particles(s.grid, Vec2(0, 0), Vec2(length, 1), 2, 2, materials, 0);
  const double c = material.p_wave_speed();
  const double v0 = 0.001 * c;
  for (std::size_t k = 0; k < p.count(); ++k) {
    p.velocity[k] = Vec2(v0 * std::sin(std::numbers::pi * p.coordinates[k].x() / (2 * length)), 0);
  }
  BarResult r;
  r.omega_exact = std::numbers::pi / (2 * length) * c;
  const double period = 2 * std::numbers::pi / r.omega_exact;
  MpmSolver solver(s, materials, std::move(p));
  const double dt = solver.courant_time_step(0.5);
  std::vector<double> crossings;
  double previous_momentum = 0.0, previous_time = 0.0;
  double energy_first = 0.0, energy_last = 0.0;
  int samples_first = 0, samples_last = 0;
  while (solver.clock().time < 5 * period) {
    solver.step(dt);
    double momentum = 0.0;
    for (std::size_t k = 0; k < solver.particles().count(); ++k) {
      momentum += solver.particles().mass[k] * solver.particles().velocity[k].x();
    }
    // The velocities are those of the half step.
    const double t = solver.clock().time - 0.5 * dt;
    if (solver.clock().step > 1 && (momentum > 0) != (previous_momentum > 0)) {
      crossings.push_back(previous_time +
                          (t - previous_time) * previous_momentum / (previous_momentum - momentum));
    }
    previous_momentum = momentum;
    previous_time = t;
    const double e = solver.energies().total();
    if (t < period) {
      energy_first += e;
      ++samples_first;
    } else if (t > 4 * period) {
      energy_last += e;
      ++samples_last;
    }
  }
  if (crossings.size() < 2) return r;
  const double measured_period = 2.0 * (crossings[crossings.size() - 1] - crossings[0]) /
                                 static_cast<double>(crossings.size() - 1);
  r.omega_numerical = 2 * std::numbers::pi / measured_period;
  r.energy_drift = (energy_last / samples_last) / (energy_first / samples_first) - 1.0;
  return r;
}

TEST(VibratingBar, FirstModeFrequencyAndEnergyForEveryShapeAndScheme) {
  for (auto shape : {ShapeFunction::gimp, ShapeFunction::linear}) {
    for (auto scheme : {UpdateScheme::musl, UpdateScheme::usl}) {
      const BarResult r = vibrating_bar(shape, scheme);
      const double error = r.omega_numerical / r.omega_exact - 1.0;
      std::printf(
          "vibrating bar %s %s: omega %.5f (exact %.5f, error %+.3f %%), energy drift %+.3f %%\n",
          to_string(shape).data(), to_string(scheme).data(), r.omega_numerical, r.omega_exact,
          100 * error, 100 * r.energy_drift);
      EXPECT_LT(std::abs(error), 0.02) << to_string(shape) << " " << to_string(scheme);
      EXPECT_LT(std::abs(r.energy_drift), 0.02) << to_string(shape) << " " << to_string(scheme);
    }
  }
}

}  // namespace
}  // namespace slide::mpm

namespace slide::mpm {
namespace {

using namespace testing;

// A block sliding on the frictional base at v0 decelerates at μg and stops after
// d = v0²/(2μg). It starts from its lithostatic (K0) stresses so that it does not drop
// onto the base. The block is Mohr–Coulomb (φ = 35° > atan μ, so it carries the base
// shear without failing): steady sliding of a purely elastic body under Coulomb friction
// with constant μ is dynamically unstable (friction-excited flutter, Adams 1995, J. Appl.
// Mech. 62:867), and FLIP, which has no numerical dissipation, lets that grow; plasticity
// bounds it, as in the soils of the cases.
TEST(SlidingBlock, StopsAfterVSquaredOverTwoMuG) {
  const double mu = 0.466, v0 = 5.0, g = 9.81;
  MpmSettings s = settings_on(Vec2(0, 0), Vec2(30, 6), 1.0);
  s.gravity = Vec2(0, -g);
  set_edge(s, edge_base, BoundaryCondition::friction);
  s.boundaries.friction_coefficient = mu;
  Material block = elastic_soil(2000.0, 2.0e8, 0.25);
  block.model = MaterialModel::mohr_coulomb;
  block.friction_angle = 35.0;
  block.cohesion = 5000.0;
  const MaterialTable materials{block};
  Particles p = generate_box_particles(s.grid, Vec2(2, 0), Vec2(6, 1), 4, 4, materials, 0);
  apply_k0_stresses(p, materials, std::vector<double>(p.count(), 1.0), g);
  for (auto& v : p.velocity) v = Vec2(v0, 0.0);
  MpmSolver solver(s, materials, std::move(p));
  auto centre = [&] {
    double mx = 0.0, m = 0.0;
    for (std::size_t k = 0; k < solver.particles().count(); ++k) {
      mx += solver.particles().mass[k] * solver.particles().coordinates[k].x();
      m += solver.particles().mass[k];
    }
    return mx / m;
  };
  const double x0 = centre();
  const double dt = solver.courant_time_step(0.5);
  const double stop_time = v0 / (mu * g);
  while (solver.clock().time < 1.5 * stop_time) solver.step(dt);
  const double distance = centre() - x0;
  const double expected = v0 * v0 / (2 * mu * g);
  std::printf("sliding block: %.4f m (expected %.4f m, error %+.2f %%)\n", distance, expected,
              100 * (distance / expected - 1));
  EXPECT_NEAR(distance / expected, 1.0, 0.03);
  EXPECT_LT(solver.energies().kinetic, 1e-4 * 0.5 * 4 * 2000 * v0 * v0);
}

}  // namespace
}  // namespace slide::mpm

namespace slide::mpm {
namespace {

using namespace testing;

struct GeostaticError {
  double max_error = 0.0;   ///< max |σyy − σyy_exact| / (ρ g H) over the particles
  double mean_error = 0.0;  ///< mean of the same
};

// A level column at rest (rollers on the walls and the base) from its exact K0 stresses,
// elastic, no damping, 1 s: how far the particle stresses wander from σyy = −ρ g (H − y)
// (the stress oscillation of MPM the method paper complains about).
GeostaticError geostatic_column(ShapeFunction shape) {
  const double g = 9.81, height = 10.0;
  MpmSettings s = settings_on(Vec2(0, 0), Vec2(10, 12), 1.0, shape);
  s.gravity = Vec2(0, -g);
  set_edge(s, edge_left, BoundaryCondition::roller);
  set_edge(s, edge_right, BoundaryCondition::roller);
  set_edge(s, edge_base, BoundaryCondition::roller);
  const Material soil = elastic_soil();
  const MaterialTable materials{soil};
  Particles p = generate_box_particles(s.grid, Vec2(0, 0), Vec2(10, height), 4, 4, materials, 0);
  apply_k0_stresses(p, materials, std::vector<double>(p.count(), height), g);
  MpmSolver solver(s, materials, std::move(p));
  const double dt = solver.courant_time_step(0.5);
  while (solver.clock().time < 1.0) solver.step(std::min(dt, 1.0 - solver.clock().time));
  GeostaticError e;
  const Particles& q = solver.particles();
  for (std::size_t k = 0; k < q.count(); ++k) {
    const double exact = -soil.density * g * (height - q.coordinates[k].y());
    const double error = std::abs(q.stress[k][1] - exact) / (soil.density * g * height);
    e.max_error = std::max(e.max_error, error);
    e.mean_error += error / static_cast<double>(q.count());
  }
  return e;
}

TEST(GeostaticColumn, StressErrorPerShapeFunction) {
  const GeostaticError gimp = geostatic_column(ShapeFunction::gimp);
  const GeostaticError linear = geostatic_column(ShapeFunction::linear);
  std::printf(
      "geostatic column, max |σyy error| / ρgH after 1 s: uGIMP %.4f (mean %.4f), linear %.4f "
      "(mean %.4f)\n",
      gimp.max_error, gimp.mean_error, linear.max_error, linear.mean_error);
  // uGIMP, the default, keeps the lithostatic stress within a few per cent of ρgH;
  // linear shape functions suffer from cell-crossing noise and are looser.
  EXPECT_LT(gimp.max_error, 0.10);
  EXPECT_LT(gimp.mean_error, 0.02);
  EXPECT_LT(linear.max_error, 0.25);
}

// Mass: particle masses never change, and the grid receives all of it (partition of
// unity). Momentum: a free body without gravity keeps Σ m v to round-off, whatever its
// internal stresses do. (Linear USL is left out: a particle entering a cell whose nodes
// carry almost no mass gets a velocity gradient ∇N·F/m that grows without bound as the
// mass goes to zero, the classic small-mass instability of USL with linear shape
// functions; MUSL, the default, re-projects the velocities and does not have it.)
TEST(Conservation, MassIsExactAndMomentumOfAFreeBodyIsKept) {
  for (auto shape : {ShapeFunction::gimp, ShapeFunction::linear}) {
    for (auto scheme : {UpdateScheme::musl, UpdateScheme::usl}) {
      if (shape == ShapeFunction::linear && scheme == UpdateScheme::usl) continue;
      MpmSettings s = settings_on(Vec2(0, 0), Vec2(20, 20), 1.0, shape, scheme);
      const MaterialTable materials{elastic_soil()};
      Particles p = generate_box_particles(s.grid, Vec2(6, 6), Vec2(12, 10), 3, 3, materials, 0);
      double scale = 0.0;
      for (std::size_t k = 0; k < p.count(); ++k) {
        const Vec2 x = p.coordinates[k];
        p.velocity[k] = Vec2(1.0 + 0.3 * std::sin(x.y()), -0.5 + 0.2 * std::cos(2 * x.x()));
        p.stress[k] = Vec4(-2e3 * x.y(), 5e2 * x.x(), 0.0, 1e2 * x.x() * x.y());
        scale += p.mass[k] * p.velocity[k].norm();
      }
      const std::vector<double> masses = p.mass;
      auto momentum = [](const Particles& q) {
        Vec2 sum = Vec2::Zero();
        for (std::size_t k = 0; k < q.count(); ++k) sum += q.mass[k] * q.velocity[k];
        return sum;
      };
      const Vec2 before = momentum(p);
      double total_mass = 0.0;
      for (double m : masses) total_mass += m;
      MpmSolver solver(s, materials, std::move(p));
      const double dt = solver.courant_time_step(0.5);
      for (int n = 0; n < 200; ++n) solver.step(dt);
      const Vec2 after = momentum(solver.particles());
      EXPECT_LT((after - before).norm(), 1e-12 * scale)
          << to_string(shape) << " " << to_string(scheme);
      EXPECT_NEAR(solver.grid_mass(), total_mass, 1e-12 * total_mass);
      for (std::size_t k = 0; k < solver.particles().count(); ++k) {
        const auto id = static_cast<std::size_t>(solver.particles().id[k]);
        EXPECT_EQ(solver.particles().mass[k], masses[id]);
      }
    }
  }
}

}  // namespace
}  // namespace slide::mpm
