// The pieces of the MPI slab decomposition that need no second rank (mpm/domain.hpp):
// the cuts, the particles' cell columns and the packing that carries particles between
// ranks. tests/mpi runs the exchanges themselves on 2 and 3 ranks.
#include <cstring>
#include <numeric>
#include <string>
#include <tuple>
#include <vector>

#include <gtest/gtest.h>

#include "common/base/error.hpp"
#include "mpm/domain.hpp"
#include "mpm/mpm_record.hpp"
#include "tests/support/mpm_builders.hpp"

namespace slide::mpm {
namespace {

using namespace testing;

std::int64_t particles_in(const SlabCuts& cuts, const std::vector<std::int64_t>& counts, int r) {
  const auto first = counts.begin() + cuts.begin[static_cast<std::size_t>(r)];
  const auto last = counts.begin() + cuts.begin[static_cast<std::size_t>(r) + 1];
  return std::accumulate(first, last, std::int64_t{0});
}

// Uniform counts: N equal slabs; every column's owner is the slab that contains it.
TEST(SlabCuts, UniformCountsGiveEqualSlabs) {
  const std::vector<std::int64_t> counts(12, 10);
  const SlabCuts cuts = SlabCuts::balanced(counts, 3);
  EXPECT_EQ(cuts.begin, (std::vector<int>{0, 4, 8, 12}));
  for (int c = 0; c < 12; ++c) EXPECT_EQ(cuts.owner_of_column(c), c / 4) << c;
  EXPECT_NO_THROW(cuts.check(12));
}

// A column-short-like load, all particles in the first quarter of the grid: each slab
// holds at most its share plus one column's particles, and is at least three cells wide.
TEST(SlabCuts, ConcentratedLoadIsBalancedWithinOneColumn) {
  std::vector<std::int64_t> counts(200, 0);
  for (int c = 0; c < 25; ++c) counts[static_cast<std::size_t>(c)] = 640 + 7 * c;
  const std::int64_t total = std::accumulate(counts.begin(), counts.end(), std::int64_t{0});
  for (int ranks : {2, 3, 5, 8}) {
    const SlabCuts cuts = SlabCuts::balanced(counts, ranks);
    ASSERT_EQ(cuts.ranks(), ranks);
    EXPECT_NO_THROW(cuts.check(200));
    for (int r = 0; r < ranks; ++r) {
      EXPECT_LE(particles_in(cuts, counts, r), total / ranks + 640 + 7 * 24)
          << ranks << " ranks, slab " << r;
    }
    // Deterministic: the same counts, the same cuts.
    EXPECT_EQ(SlabCuts::balanced(counts, ranks).begin, cuts.begin);
  }
}

// All particles in one column: the minimum width still holds, pushed from both ends.
TEST(SlabCuts, EverySlabIsAtLeastThreeCellsWide) {
  for (int hot : {0, 5, 11}) {
    std::vector<std::int64_t> counts(12, 0);
    counts[static_cast<std::size_t>(hot)] = 1000;
    const SlabCuts cuts = SlabCuts::balanced(counts, 4);
    EXPECT_EQ(cuts.begin, (std::vector<int>{0, 3, 6, 9, 12})) << "all in column " << hot;
  }
  const std::vector<std::int64_t> empty(9, 0);
  EXPECT_NO_THROW(SlabCuts::balanced(empty, 3).check(9));
}

TEST(SlabCuts, TooManyRanksOrBadCutsAreErrors) {
  const std::vector<std::int64_t> counts(8, 1);
  EXPECT_THROW(SlabCuts::balanced(counts, 3), Error);  // 3 × 3 > 8 columns
  EXPECT_THROW(SlabCuts::balanced(counts, 0), Error);
  EXPECT_THROW((SlabCuts{{0, 2, 8}}.check(8)), Error);  // a slab of 2 cells
  EXPECT_THROW((SlabCuts{{0, 4, 7}}.check(8)), Error);  // short of the grid's end
  EXPECT_THROW((SlabCuts{{1, 4, 8}}.check(8)), Error);
}

// A particle's column: its cell's, the half-cell margins counting as the edge columns.
TEST(CellColumn, MarginsBelongToTheEdgeColumns) {
  const GridGeometry grid = GridGeometry::covering(Vec2(0, 0), Vec2(10, 4), 1.0);
  EXPECT_EQ(cell_column_of(grid, Vec2(0.5, 1)), 0);
  EXPECT_EQ(cell_column_of(grid, Vec2(3.999, 1)), 3);
  EXPECT_EQ(cell_column_of(grid, Vec2(4.0, 1)), 4);
  EXPECT_EQ(cell_column_of(grid, Vec2(-0.3, 1)), 0);
  EXPECT_EQ(cell_column_of(grid, Vec2(10.3, 1)), grid.cells_x - 1);
}

/// Every field of particle k, as bytes, in declaration order.
std::vector<std::byte> bytes_of_particle(const Particles& p, std::size_t k, bool affine) {
  std::vector<std::byte> out;
  auto add = [&](const auto& v) {
    const auto* b = reinterpret_cast<const std::byte*>(&v);
    out.insert(out.end(), b, b + sizeof(v));
  };
  add(p.coordinates[k]), add(p.displacement[k]), add(p.velocity[k]), add(p.stress[k]);
  add(p.strain[k]), add(p.eps_q[k]), add(p.pore_pressure[k]), add(p.volume[k]);
  add(p.mass[k]), add(p.size[k]), add(p.material_id[k]), add(p.element[k]), add(p.id[k]);
  add(p.state[k].plastic_shear_strain), add(p.state[k].plastic_volumetric_strain);
  add(p.state[k].peak_strength);
  for (const auto& s : p.surface_stress.of(k)) add(s);
  if (affine) add(p.affine_velocity[k]);
  return out;
}

/// n particles whose every field (surface stresses and affine state included) holds a
/// value of its own.
Particles distinct_particles(std::size_t n, std::size_t surfaces) {
  Particles p;
  p.surface_stress.per_point = surfaces;
  p.affine_velocity.resize(1);  // resize keeps an affine field only when it is not empty
  p.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    const double f = 1.0 + static_cast<double>(k);
    p.coordinates[k] = Vec2(f, f + 0.1);
    p.displacement[k] = Vec2(f + 0.2, f + 0.3);
    p.velocity[k] = Vec2(-f, f / 3);
    p.stress[k] = Vec4(f, 2 * f, 3 * f, 4 * f) * -1e3;
    p.strain[k] = Vec4(f, -f, 0.5 * f, f / 7) * 1e-4;
    p.eps_q[k] = f / 11;
    p.pore_pressure[k] = 10 * f;
    p.volume[k] = 0.0625 * f;
    p.mass[k] = 106.25 * f;
    p.size[k] = Vec2(0.25, 0.5 * f);
    p.material_id[k] = static_cast<std::int32_t>(k % 3);
    p.element[k] = static_cast<std::int64_t>(k) * 5 - 1;
    p.id[k] = static_cast<std::int64_t>(k) + 1000;
    p.state[k] = {f / 13, -f / 17, 5e4 * f};
    for (std::size_t s = 0; s < surfaces; ++s)
      p.surface_stress.of(k)[s] = Vec4(f, static_cast<double>(s), -f, static_cast<double>(s) * f);
    p.affine_velocity[k] = Vec4(f, -f, f / 2, -f / 2);
  }
  p.check_consistent_sizes();
  return p;
}

// Packing then unpacking gives every field of every row back bit for bit, appended in
// the order of the indices, with and without surface stresses and affine state.
TEST(ParticlePacking, RoundTripIsBitExactForEveryField) {
  for (std::size_t surfaces : {std::size_t{0}, std::size_t{3}}) {
    for (bool affine : {true, false}) {
      const PackedLayout layout{surfaces, affine};
      Particles from = distinct_particles(7, surfaces);
      if (!affine) from.affine_velocity.clear();
      const std::vector<std::size_t> rows{5, 0, 3};
      std::vector<std::byte> bytes;
      pack_particles(from, rows, layout, bytes);
      ASSERT_EQ(bytes.size(), rows.size() * layout.bytes());

      Particles to = distinct_particles(2, surfaces);
      if (!affine) to.affine_velocity.clear();
      ASSERT_EQ(unpack_particles(bytes, layout, to), rows.size());
      ASSERT_EQ(to.count(), 2 + rows.size());
      to.check_consistent_sizes();
      for (std::size_t i = 0; i < rows.size(); ++i) {
        EXPECT_EQ(bytes_of_particle(to, 2 + i, affine), bytes_of_particle(from, rows[i], affine))
            << "row " << rows[i] << ", " << surfaces << " surfaces, affine " << affine;
      }
      EXPECT_EQ(to.id[0], 1000);  // the particles already there are left alone
    }
  }
}

// A rank all of whose particles left holds no affine field (Particles::resize keeps an
// empty one empty): the run's layout, not the particles, tells that rows carry one, and
// the arrivals bring it back.
TEST(ParticlePacking, AnEmptyApicRankTakesAffineRows) {
  const PackedLayout apic{0, true};
  const Particles from = distinct_particles(3, 0);
  std::vector<std::byte> bytes;
  const std::vector<std::size_t> rows{2, 1};
  pack_particles(from, rows, apic, bytes);
  Particles empty = distinct_particles(1, 0);
  empty.resize(0);
  ASSERT_TRUE(empty.affine_velocity.empty());
  ASSERT_EQ(unpack_particles(bytes, apic, empty), 2u);
  ASSERT_EQ(empty.affine_velocity.size(), 2u);
  EXPECT_EQ(bytes_of_particle(empty, 0, true), bytes_of_particle(from, 2, true));
  EXPECT_EQ(bytes_of_particle(empty, 1, true), bytes_of_particle(from, 1, true));
}

TEST(ParticlePacking, APartialRowOrAnotherLayoutIsAnError) {
  const PackedLayout flip{0, false};
  Particles from = distinct_particles(2, 0);
  std::vector<std::byte> bytes;
  const std::vector<std::size_t> rows{1};
  pack_particles(from, rows, flip, bytes);
  bytes.pop_back();
  Particles to = distinct_particles(1, 0);
  EXPECT_THROW(unpack_particles(bytes, flip, to), Error);
  EXPECT_THROW(unpack_particles(bytes, PackedLayout{2, false}, to), Error);  // surfaces
  from.affine_velocity.clear();
  EXPECT_THROW(pack_particles(from, rows, PackedLayout{0, true}, bytes), Error);
}

// On one process the decomposition is the whole grid: distribute changes nothing, the
// part of the set is all of it, and a Subdomain of one slab keeps every particle and owns
// every node column.
TEST(Subdomain, OneRankOwnsEverything) {
  const MpmSettings s = settings_on(Vec2(0, 0), Vec2(10, 4), 1.0);
  const MaterialTable materials{elastic_soil()};
  Particles p = generate_box_particles(s.grid, Vec2(1, 0), Vec2(9, 2), 2, 2, materials, 0);
  const std::size_t n = p.count();
  EXPECT_EQ(keep_part(p, 3, Ranks::single()), 3u);
  EXPECT_EQ(p.count(), n);
  const Subdomain one(Ranks::single(), SlabCuts{{0, s.grid.cells_x}});
  EXPECT_EQ(one.scatter(p, 0, s.grid, PackedLayout{}), n);
  EXPECT_EQ(p.count(), n);
  EXPECT_EQ(one.own_node_columns(s.grid), std::make_pair(0, s.grid.node_columns()));
  MpmSolver solver(s, materials, std::move(p));
  solver.distribute(Ranks::single());
  EXPECT_EQ(solver.subdomain(), nullptr);
  EXPECT_EQ(solver.active_count(), n);
}

// A restart's holders: the file's rows are every rank's active rows in rank order, then
// every rank's frozen rows. Rows 0-4 active on rank 0, 5-11 on rank 1, 12 frozen on
// rank 0, 13-14 frozen on rank 1; a part of rows 3-13 has 9 active rows (3-11).
TEST(HeldRows, EachRowGoesBackToItsHolder) {
  HeldRows held{{5, 7}, {1, 2}, 3};
  const std::vector<int> expected{0, 0, 1, 1, 1, 1, 1, 1, 1, 0, 1};
  for (std::size_t i = 0; i < expected.size(); ++i) EXPECT_EQ(held.holder(i, 9), expected[i]) << i;
  EXPECT_THROW(held.holder(12, 9), Error);  // row 15: the file has 15
}

MpmRecord record_with(std::string cuts, std::string rows, std::int64_t frozen) {
  MpmRecord r;
  r.slab_cuts = std::move(cuts);
  r.slab_rows = std::move(rows);
  r.frozen_particles = frozen;
  return r;
}

// The recorded slabs and rows are taken on as many ranks, ignored on others, and refused
// with the attribute's name when they cannot describe the file.
TEST(RestartSlabs, TakenOnAsManyRanksAndCheckedAgainstTheFile) {
  const auto d = restart_slabs(record_with("0 25 200", "5 7 1 2", 3), 15, 3, 2, "f.h5");
  ASSERT_TRUE(d && d->cuts && d->held);
  EXPECT_EQ(d->cuts->begin, (std::vector<int>{0, 25, 200}));
  EXPECT_EQ(d->held->active, (std::vector<std::int64_t>{5, 7}));
  EXPECT_EQ(d->held->frozen, (std::vector<std::int64_t>{1, 2}));
  EXPECT_EQ(d->held->first_row, 3u);
  EXPECT_FALSE(restart_slabs(record_with("0 25 200", "5 7 1 2", 3), 15, 0, 3, "f.h5"));
  EXPECT_FALSE(restart_slabs(record_with("", "", 0), 15, 0, 2, "f.h5"));
  // Written before the rows were recorded: slabs only, particles to their cells' slabs.
  const auto old = restart_slabs(record_with("0 25 200", "", 3), 15, 0, 2, "f.h5");
  ASSERT_TRUE(old && old->cuts);
  EXPECT_FALSE(old->held);
  for (const auto& [cuts, rows, frozen] :
       std::vector<std::tuple<std::string, std::string, std::int64_t>>{
           {"0 x 200", "5 7 1 2", 3},    // not columns
           {"0 25 200", "5 7 1", 3},     // 3 counts for 2 ranks
           {"0 25 200", "5 7 1 1", 2},   // 14 rows, the file has 15
           {"0 25 200", "6 7 -1 3", 2},  // negative
           {"0 25 200", "5 7 2 1", 2},   // 3 frozen rows, the record says 2
       }) {
    try {
      restart_slabs(record_with(cuts, rows, frozen), 15, 0, 2, "f.h5");
      ADD_FAILURE() << cuts << " | " << rows;
    } catch (const Error& e) {
      EXPECT_EQ(std::string(e.what()).rfind("f.h5: /solver attribute slab_", 0), 0u) << e.what();
    }
  }
}

}  // namespace
}  // namespace slide::mpm
