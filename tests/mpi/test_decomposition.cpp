// mpm-solve's slab decomposition on several ranks (mpm/domain.hpp, docs/parallel.md)
// against the same run on one process, which every rank also makes, and against the
// closed form: a block sliding on a Coulomb base stops after v0²/(2μg) (the serial
// SlidingBlock test), here across every cut between the ranks.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "common/base/ranks.hpp"
#include "mpm/domain.hpp"
#include "tests/support/mpm_builders.hpp"

namespace slide::mpm {
namespace {

using namespace testing;

const Ranks& ranks() {
  return Ranks::world();
}

/// One particle as the root compares it.
struct Row {
  std::int64_t id;
  double mass, x, y, vx, vy, sxx, syy, sxy;
};

/// Every rank's active particles on the root, by id (empty on the other ranks).
std::vector<Row> rows_on_root(const MpmSolver& solver) {
  const Particles& p = solver.particles();
  std::vector<Row> mine;
  for (std::size_t k = 0; k < solver.active_count(); ++k) {
    mine.push_back({p.id[k], p.mass[k], p.coordinates[k].x(), p.coordinates[k].y(),
                    p.velocity[k].x(), p.velocity[k].y(), p.stress[k][0], p.stress[k][1],
                    p.stress[k][3]});
  }
  auto all = Ranks::values_of<Row>(
      solver.ranks().gather_to_root(Ranks::bytes_of(std::span<const Row>(mine))));
  std::sort(all.begin(), all.end(), [](const Row& a, const Row& b) { return a.id < b.id; });
  return all;
}

struct Totals {
  double mass = 0, momentum_x = 0, momentum_y = 0, mass_x = 0;
};

/// Σ over all ranks (the serial solver's ranks are one process).
Totals totals_of(const MpmSolver& solver) {
  const Particles& p = solver.particles();
  std::vector<double> t(4, 0.0);
  for (std::size_t k = 0; k < solver.active_count(); ++k) {
    t[0] += p.mass[k];
    t[1] += p.mass[k] * p.velocity[k].x();
    t[2] += p.mass[k] * p.velocity[k].y();
    t[3] += p.mass[k] * p.coordinates[k].x();
  }
  solver.ranks().sum(std::span<double>(t));
  return {t[0], t[1], t[2], t[3]};
}

/// The sliding block of tests/mpm/test_physics.cpp, faster (10 m/s, a 10.9 m slide) on
/// a longer floor: it starts in cell columns 2–5 and stops with its back beyond column 12.
struct SlidingBlock {
  static constexpr double mu = 0.466, v0 = 10.0, g = 9.81;
  MpmSettings settings = on_a_frictional_base(Vec2(40, 6), mu, g);
  MaterialTable materials;
  Particles particles;

  explicit SlidingBlock(VelocityTransfer transfer = VelocityTransfer::flip_pic) {
    settings.velocity_transfer = transfer;
    Material block = elastic_soil(2000.0, 2.0e8, 0.25);
    block.model = MaterialModel::mohr_coulomb;
    block.friction_angle = 35.0;
    block.cohesion = 5000.0;
    materials = {block};
    particles = generate_box_particles(settings.grid, Vec2(2, 0), Vec2(6, 1), 4, 4, materials, 0);
    apply_k0_stresses(particles, materials, std::vector<double>(particles.count(), 1.0), g);
    for (auto& v : particles.velocity) v = Vec2(v0, 0.0);
  }
  /// This rank's part of the block, as distribute takes it.
  Particles part() const {
    Particles p = particles;
    keep_part(p, 0, ranks());
    return p;
  }
  double stop_time() const { return v0 / (mu * g); }
  double slide() const { return v0 * v0 / (2 * mu * g); }
};

/// Steps both solvers with the serial one's Courant step to 1.5 stop times; checks mass
/// and momentum of the distributed run against the serial one at every step.
void run_side_by_side(MpmSolver& serial, MpmSolver& distributed, double stop_time) {
  const double dt = serial.courant_time_step(0.5);
  EXPECT_EQ(distributed.courant_time_step(0.5), dt);  // a max over ranks: exact
  const Totals start = totals_of(serial);
  const double p_scale = start.mass * SlidingBlock::v0;
  int steps = 0;
  while (serial.clock().time < 1.5 * stop_time) {
    serial.step(dt);
    distributed.step(dt);
    ++steps;
    const Totals a = totals_of(serial), b = totals_of(distributed);
    // The same particles, whose masses never change: the mass is the same up to the
    // order of summation.
    EXPECT_NEAR(b.mass, a.mass, 1e-14 * a.mass) << "step " << steps;
    EXPECT_NEAR(b.momentum_x, a.momentum_x, 1e-11 * p_scale) << "step " << steps;
    EXPECT_NEAR(b.momentum_y, a.momentum_y, 1e-11 * p_scale) << "step " << steps;
    EXPECT_NEAR(distributed.last_kinetic_energy(), serial.last_kinetic_energy(),
                1e-11 * 0.5 * p_scale * SlidingBlock::v0)
        << "step " << steps;
    if (::testing::Test::HasFailure()) return;
  }
  if (distributed.ranks().root()) std::printf("  %d steps of %.3g ms\n", steps, 1e3 * dt);
}

/// The root's comparison of the two runs' particles, by id.
void expect_same_particles(const MpmSolver& serial, const MpmSolver& distributed) {
  const auto a = rows_on_root(serial);
  const auto b = rows_on_root(distributed);
  if (!distributed.ranks().root()) return;
  // The serial solver gathers on its own single process: every rank holds its rows.
  ASSERT_EQ(a.size(), b.size());
  double dx = 0, dv = 0, ds = 0, smax = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    ASSERT_EQ(a[i].id, b[i].id);
    EXPECT_EQ(a[i].mass, b[i].mass) << "id " << a[i].id;  // carried, never recomputed
    dx = std::max({dx, std::abs(a[i].x - b[i].x), std::abs(a[i].y - b[i].y)});
    dv = std::max({dv, std::abs(a[i].vx - b[i].vx), std::abs(a[i].vy - b[i].vy)});
    ds = std::max({ds, std::abs(a[i].sxx - b[i].sxx), std::abs(a[i].syy - b[i].syy),
                   std::abs(a[i].sxy - b[i].sxy)});
    smax = std::max({smax, std::abs(a[i].sxx), std::abs(a[i].syy)});
  }
  std::printf("  %d ranks against one: max |Δx| %.2e m, |Δv| %.2e m/s, |Δσ| %.2e of max |σ|\n",
              distributed.ranks().size(), dx, dv, ds / smax);
  EXPECT_LT(dx, 1e-9);
  EXPECT_LT(dv, 1e-9 * SlidingBlock::v0);
  EXPECT_LT(ds, 1e-9 * smax);
}

// Migration stress test: cuts fixed between columns 7 and 12 and never re-cut, so the
// whole block, which starts on rank 0, crosses every cut and ends on the last rank; the
// other ranks start with no particle at all.
void cross_every_cut(VelocityTransfer transfer) {
  const int n = ranks().size();
  SlidingBlock case_(transfer);
  MpmSolver serial(case_.settings, case_.materials, case_.particles);
  MpmSolver distributed(case_.settings, case_.materials, case_.part());
  Decomposition fixed;
  fixed.cuts = n == 2 ? SlabCuts{{0, 9, 40}} : SlabCuts{{0, 7, 10, 40}};
  fixed.rebalance_share = std::numeric_limits<double>::infinity();
  distributed.distribute(ranks(), fixed);
  const Subdomain* domain = distributed.subdomain();
  ASSERT_NE(domain, nullptr);

  const auto all = static_cast<std::int64_t>(case_.particles.count());
  const auto here = static_cast<std::int64_t>(distributed.active_count());
  EXPECT_EQ(here, ranks().rank() == 0 ? all : 0) << "the block starts in slab 0";
  const double x0 = totals_of(serial).mass_x / totals_of(serial).mass;

  run_side_by_side(serial, distributed, case_.stop_time());

  const auto end = static_cast<std::int64_t>(distributed.active_count());
  EXPECT_EQ(end, ranks().rank() == n - 1 ? all : 0) << "the block ends in the last slab";
  EXPECT_EQ(domain->recuts, 0);
  EXPECT_GT(ranks().sum(static_cast<double>(domain->bytes_sent)), 0.0);
  expect_same_particles(serial, distributed);
  const Totals t = totals_of(distributed);
  const double distance = t.mass_x / t.mass - x0;
  if (ranks().root()) {
    std::printf("  slide %.4f m (v0²/2μg = %.4f m, %+.2f %%)\n", distance, case_.slide(),
                100 * (distance / case_.slide() - 1));
  }
  EXPECT_NEAR(distance / case_.slide(), 1.0, 0.03);
}

TEST(Decomposition, SlidingBlockCrossesEveryCut) {
  if (ranks().size() > 3) GTEST_SKIP() << "the fixed cuts fit 2 or 3 ranks";
  cross_every_cut(VelocityTransfer::flip_pic);
}

// APIC carries an affine velocity per particle, which the ranks that start empty must
// take from their first arrivals on.
TEST(Decomposition, ApicSlidingBlockCrossesEveryCut) {
  if (ranks().size() > 3) GTEST_SKIP() << "the fixed cuts fit 2 or 3 ranks";
  cross_every_cut(VelocityTransfer::apic);
}

// keep_part: the ranks' parts are the whole set, in order, each contiguous, with the
// frozen rows last in the parts that hold them.
TEST(Decomposition, PartsOfTheWholeSet) {
  const MpmSettings s = settings_on(Vec2(0, 0), Vec2(10, 4), 1.0);
  const MaterialTable materials{elastic_soil()};
  Particles whole = generate_box_particles(s.grid, Vec2(1, 0), Vec2(6, 1), 1, 1, materials, 0);
  ASSERT_EQ(whole.count(), 5u);
  const std::size_t frozen = 2;  // the last two rows
  Particles part = whole;
  const auto part_frozen = static_cast<std::int64_t>(keep_part(part, frozen, ranks()));
  const auto ids = Ranks::values_of<std::int64_t>(
      ranks().gather_to_root(Ranks::bytes_of(std::span<const std::int64_t>(part.id))));
  if (ranks().root()) {
    EXPECT_EQ(ids, whole.id);
  }
  EXPECT_EQ(ranks().sum(static_cast<double>(part_frozen)), static_cast<double>(frozen));
  for (std::size_t k = 0; k < part.count(); ++k) {
    const bool is_frozen = part.id[k] == whole.id[3] || part.id[k] == whole.id[4];
    EXPECT_EQ(is_frozen, k + static_cast<std::size_t>(part_frozen) >= part.count()) << k;
  }
}

// Load balance: balanced cuts that the ranks re-cut as the block moves right, with the
// same result as one process.
TEST(Decomposition, ReCutsFollowTheBlock) {
  SlidingBlock case_;
  MpmSolver serial(case_.settings, case_.materials, case_.particles);
  MpmSolver distributed(case_.settings, case_.materials, case_.part());
  distributed.distribute(ranks());
  const Subdomain* domain = distributed.subdomain();
  ASSERT_NE(domain, nullptr);
  run_side_by_side(serial, distributed, case_.stop_time());
  EXPECT_GE(domain->recuts, 1);
  // Balanced within the re-cut share plus one column of particles (4 × 4 a cell, one
  // cell high) at the last re-cut, whatever moved since.
  const auto largest = ranks().max(static_cast<std::int64_t>(distributed.active_count()));
  const double mean = static_cast<double>(case_.particles.count()) / ranks().size();
  EXPECT_LE(static_cast<double>(largest), (1.0 + default_rebalance_share) * mean + 16.0);
  expect_same_particles(serial, distributed);
}

}  // namespace
}  // namespace slide::mpm
