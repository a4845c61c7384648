// The particle-reordering kernels (mpm/kernels.hpp): the in-place sort by cell and the
// retirement of particles that left the grid move whole particles (every field with its
// particle), keep the order they promise, and lose or duplicate nothing.
#include <algorithm>
#include <cmath>
#include <numeric>

#include <gtest/gtest.h>

#include "mpm/kernels.hpp"
#include "tests/support/mpm_builders.hpp"

namespace slide::mpm {
namespace {

using namespace testing;

/// n particles scattered over the grid (a fixed pseudo-random sequence), every field a
/// distinct function of the particle's id so that a mixed-up field shows.
Particles scattered_particles(const GridGeometry& grid, std::size_t n) {
  Particles p;
  p.resize(n);
  const Vec2 top = grid.upper_corner();
  for (std::size_t k = 0; k < n; ++k) {
    const double a = std::fmod(0.618033988749895 * static_cast<double>(k + 1), 1.0);
    const double b = std::fmod(0.754877666246693 * static_cast<double>(k + 1), 1.0);
    const auto id = static_cast<double>(k);
    p.coordinates[k] = Vec2(grid.origin.x() + a * (top.x() - grid.origin.x()),
                            grid.origin.y() + b * (top.y() - grid.origin.y()));
    p.displacement[k] = Vec2(id + 0.1, id + 0.2);
    p.velocity[k] = Vec2(id + 0.3, id + 0.4);
    p.stress[k] = Vec4(id + 1, id + 2, id + 3, id + 4);
    p.strain[k] = Vec4(id + 5, id + 6, id + 7, id + 8);
    p.eps_q[k] = id + 9;
    p.pore_pressure[k] = id + 10;
    p.volume[k] = id + 11;
    p.mass[k] = id + 12;
    p.size[k] = Vec2(id + 13, id + 14);
    p.material_id[k] = static_cast<std::int32_t>(k % 7);
    p.element[k] = static_cast<std::int64_t>(k) + 15;
    p.id[k] = static_cast<std::int64_t>(k);
    p.state[k] = MaterialState{id + 16, id + 17};
  }
  p.affine_velocity.resize(n);  // APIC's field, carried when present
  for (std::size_t k = 0; k < n; ++k) {
    const auto id = static_cast<double>(k);
    p.affine_velocity[k] = Vec4(id + 18, id + 19, id + 20, id + 21);
  }
  return p;
}

/// Every field of particle k still belongs to particle id[k] (and its position to the
/// same particle of `original`).
void expect_whole(const Particles& p, const Particles& original) {
  for (std::size_t k = 0; k < p.count(); ++k) {
    const auto i = static_cast<std::size_t>(p.id[k]);
    const auto id = static_cast<double>(i);
    ASSERT_EQ(p.coordinates[k], original.coordinates[i]) << k;
    ASSERT_EQ(p.displacement[k], Vec2(id + 0.1, id + 0.2)) << k;
    ASSERT_EQ(p.velocity[k], original.velocity[i]) << k;
    ASSERT_EQ(p.stress[k], Vec4(id + 1, id + 2, id + 3, id + 4)) << k;
    ASSERT_EQ(p.strain[k], Vec4(id + 5, id + 6, id + 7, id + 8)) << k;
    ASSERT_EQ(p.eps_q[k], id + 9) << k;
    ASSERT_EQ(p.pore_pressure[k], id + 10) << k;
    ASSERT_EQ(p.volume[k], id + 11) << k;
    ASSERT_EQ(p.mass[k], id + 12) << k;
    ASSERT_EQ(p.size[k], Vec2(id + 13, id + 14)) << k;
    ASSERT_EQ(p.material_id[k], static_cast<std::int32_t>(i % 7)) << k;
    ASSERT_EQ(p.element[k], static_cast<std::int64_t>(i) + 15) << k;
    ASSERT_EQ(p.state[k].plastic_shear_strain, id + 16) << k;
    ASSERT_EQ(p.state[k].plastic_volumetric_strain, id + 17) << k;
    ASSERT_EQ(p.affine_velocity[k], original.affine_velocity[i]) << k;
  }
}

TEST(SortByCell, StableByCellWithWholeParticlesAndFrozenOnesLast) {
  const GridGeometry grid = GridGeometry::covering(Vec2(0, 0), Vec2(12, 7), 1.0);
  const std::size_t n = 3000, frozen = 100;
  const Particles original = scattered_particles(grid, n);
  Particles p = original;
  sort_particles_by_cell(p, n - frozen, grid);
  ASSERT_EQ(p.count(), n);
  p.check_consistent_sizes();
  expect_whole(p, original);
  // Active particles by cell, ids (their old order) ascending within a cell: stable.
  for (std::size_t k = 1; k < n - frozen; ++k) {
    const std::size_t a = grid.cell_of(p.coordinates[k - 1]), b = grid.cell_of(p.coordinates[k]);
    ASSERT_LE(a, b) << k;
    if (a == b) {
      ASSERT_LT(p.id[k - 1], p.id[k]) << k;
    }
  }
  // The frozen particles kept their place and order at the end.
  for (std::size_t k = n - frozen; k < n; ++k) ASSERT_EQ(p.id[k], static_cast<std::int64_t>(k));
  // A permutation: every id once.
  std::vector<std::int64_t> ids = p.id;
  std::sort(ids.begin(), ids.end());
  std::vector<std::int64_t> expected(n);
  std::iota(expected.begin(), expected.end(), 0);
  EXPECT_EQ(ids, expected);
  // Sorting a sorted body changes nothing.
  Particles again = p;
  sort_particles_by_cell(again, n - frozen, grid);
  EXPECT_EQ(again.id, p.id);
}

TEST(RetireParticles, FreezeMovesThemBehindTheActiveOnesAndRemoveDeletesThem) {
  const GridGeometry grid = GridGeometry::covering(Vec2(0, 0), Vec2(12, 7), 1.0);
  const std::size_t n = 500, active = 480;  // 20 frozen already
  const Particles original = scattered_particles(grid, n);
  const std::vector<std::size_t> leaving = {0, 7, 8, 250, 479};
  for (ParticleExit mode : {ParticleExit::freeze, ParticleExit::remove}) {
    Particles p = original;
    const std::size_t new_active = retire_particles(p, active, leaving, mode);
    EXPECT_EQ(new_active, active - leaving.size());
    p.check_consistent_sizes();
    // The active ones that stay, in their order.
    std::vector<std::int64_t> expected;
    for (std::size_t k = 0; k < active; ++k) {
      if (std::find(leaving.begin(), leaving.end(), k) == leaving.end())
        expected.push_back(static_cast<std::int64_t>(k));
    }
    // Freeze: the leaving ones, then the frozen ones before; remove: the frozen ones only.
    if (mode == ParticleExit::freeze) {
      for (std::size_t k : leaving) expected.push_back(static_cast<std::int64_t>(k));
    }
    for (std::size_t k = active; k < n; ++k) expected.push_back(static_cast<std::int64_t>(k));
    ASSERT_EQ(p.id, expected);
    for (std::size_t k = 0; k < p.count(); ++k) {
      const auto i = static_cast<std::size_t>(p.id[k]);
      const bool left = std::find(leaving.begin(), leaving.end(), i) != leaving.end();
      // A frozen particle stops (its affine velocity too); everything else is that
      // particle's own.
      EXPECT_EQ(p.velocity[k], left ? Vec2::Zero().eval() : original.velocity[i]) << k;
      EXPECT_EQ(p.affine_velocity[k], left ? Vec4::Zero().eval() : original.affine_velocity[i])
          << k;
    }
    Particles stopped = original;
    for (std::size_t k : leaving) {
      stopped.velocity[k].setZero();
      stopped.affine_velocity[k].setZero();
    }
    expect_whole(p, stopped);
  }
}

}  // namespace
}  // namespace slide::mpm
