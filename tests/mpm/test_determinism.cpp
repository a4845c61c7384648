// Bit-identical results: the scatter has no atomics and sums in block order, and the
// number of blocks depends on the particle count only, so a run reproduces itself on
// the same and on a different number of threads.
#include <cstring>

#include <gtest/gtest.h>
#include <omp.h>

#include "tests/support/mpm_builders.hpp"

namespace slide::mpm {
namespace {

using namespace testing;

/// A collapsing frictional column large enough for the kernels to run in parallel.
Particles collapse(int threads, int steps, VelocityTransfer transfer = VelocityTransfer::flip_pic,
                   VolumetricSmoothing smoothing = VolumetricSmoothing::none) {
  omp_set_num_threads(threads);
  MpmSettings s = settings_on(Vec2(0, 0), Vec2(80, 20), 1.0);
  s.velocity_transfer = transfer;
  s.volumetric_smoothing = smoothing;
  s.gravity = Vec2(0, -9.81);
  set_edge(s, edge_left, BoundaryCondition::roller);
  set_edge(s, edge_base, BoundaryCondition::friction);
  s.boundaries.friction_coefficient = 0.466;
  s.sort_interval = 7;
  const MaterialTable materials{frictional_soil()};
  Particles p = generate_box_particles(s.grid, Vec2(0, 0), Vec2(40, 16), 4, 4, materials, 0);
  apply_k0_stresses(p, materials, std::vector<double>(p.count(), 16.0));
  MpmSolver solver(s, materials, std::move(p));
  solver.return_to_yield_surface();
  const double dt = solver.courant_time_step(0.5);
  for (int n = 0; n < steps; ++n) solver.step(dt);
  return solver.particles();
}

/// (An empty vector's data() may be null, which memcmp must not be given even for 0 bytes.)
template <class T>
bool same_bits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() &&
         (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

void expect_identical(const Particles& a, const Particles& b) {
  EXPECT_TRUE(same_bits(a.coordinates, b.coordinates));
  EXPECT_TRUE(same_bits(a.velocity, b.velocity));
  EXPECT_TRUE(same_bits(a.displacement, b.displacement));
  EXPECT_TRUE(same_bits(a.stress, b.stress));
  EXPECT_TRUE(same_bits(a.strain, b.strain));
  EXPECT_TRUE(same_bits(a.volume, b.volume));
  EXPECT_TRUE(same_bits(a.id, b.id));
  EXPECT_TRUE(same_bits(a.affine_velocity, b.affine_velocity));
}

TEST(Determinism, TwoThreadsTwiceAndOneThreadAreBitIdentical) {
  const int steps = 40;
  const Particles first = collapse(2, steps);
  ASSERT_GE(first.count(), 8192u);  // the parallel path
  const Particles second = collapse(2, steps);
  expect_identical(first, second);
  const Particles serial = collapse(1, steps);
  expect_identical(first, serial);
  // And it moved: the test compares a collapse, not a body at rest.
  double largest = 0.0;
  for (const Vec2& u : first.displacement) largest = std::max(largest, u.norm());
  EXPECT_GT(largest, 0.05);
}

TEST(Determinism, ApicTwoThreadsAndOneThreadAreBitIdentical) {
  const int steps = 40;
  const Particles first = collapse(2, steps, VelocityTransfer::apic);
  ASSERT_EQ(first.affine_velocity.size(), first.count());
  expect_identical(first, collapse(2, steps, VelocityTransfer::apic));
  expect_identical(first, collapse(1, steps, VelocityTransfer::apic));
  double largest = 0.0;
  for (const Vec4& b : first.affine_velocity) largest = std::max(largest, b.cwiseAbs().maxCoeff());
  EXPECT_GT(largest, 0.0);
}

// The cell averages are summed in block order too.
TEST(Determinism, VolumetricSmoothingTwoThreadsAndOneThreadAreBitIdentical) {
  const int steps = 40;
  const auto run = [&](int threads) {
    return collapse(threads, steps, VelocityTransfer::apic, VolumetricSmoothing::cell);
  };
  const Particles first = run(2);
  expect_identical(first, run(2));
  expect_identical(first, run(1));
  // And smoothing changed the run.
  const Particles unsmoothed = collapse(2, steps, VelocityTransfer::apic);
  EXPECT_FALSE(same_bits(first.stress, unsmoothed.stress));
}

}  // namespace
}  // namespace slide::mpm
