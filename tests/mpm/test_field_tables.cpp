// The field tables drive every path a field takes (common/physics/field_table.hpp). Each
// test plants in every field of the table, generically (a value of its own per field and
// per particle, a function of the particle's id), sends the particles through one path
// (the sort's permutation, resize, MPI packing, the checkpoint writer and reader) and
// checks, field by field, that every value arrives with its particle. Since each loop
// runs over the table, a field added to Particles is covered the day it is added to
// particle_fields (and a member left out of it fails to compile: the static_assert
// beside the table); a path that named fields by hand would lose the new one here.
// The schema page (common/io/checkpoint-schema.md) is checked against both tables.
#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <map>
#include <numeric>
#include <random>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "common/base/error.hpp"
#include "common/io/checkpoint.hpp"
#include "common/physics/fe_fields.hpp"
#include "common/physics/particles.hpp"
#include "mpm/domain.hpp"
#include "mpm/kernels.hpp"
#include "tools/synthetic/soil.hpp"

namespace slide {
namespace {

/// The value field `f` holds for the particle of id `id` (as a double).
double planted(std::size_t f, std::int64_t id, std::size_t component = 0) {
  return 1000.0 * static_cast<double>(f + 1) + static_cast<double>(id) +
         0.125 * static_cast<double>(component);
}

template <class T>
T planted_entry(std::size_t f, std::int64_t id) {
  if constexpr (std::is_same_v<T, MaterialState>) {
    MaterialState s;
    std::size_t c = 0;
    for (const StateField& member : material_state_fields) s.*member.member = planted(f, id, c++);
    return s;
  } else if constexpr (std::is_arithmetic_v<T>) {
    return static_cast<T>(planted(f, id));
  } else {
    T v;
    for (int c = 0; c < v.size(); ++c) v[c] = planted(f, id, static_cast<std::size_t>(c));
    return v;
  }
}

template <class T>
bool same(const T& a, const T& b) {
  if constexpr (std::is_same_v<T, MaterialState>) {
    for (const StateField& member : material_state_fields) {
      if (a.*member.member != b.*member.member) return false;
    }
    return true;
  } else {
    return a == b;
  }
}

/// n particles with ids 10, 11, …; every field planted except `id` itself, which the
/// values are functions of, and the positions, which follow a zigzag so that a sort by
/// cell reorders them. Three multi-yield surfaces and an affine velocity per particle.
Particles planted_particles(std::size_t n) {
  Particles p;
  p.surface_stress.per_point = 3;
  p.affine_velocity.assign(1, Vec4::Zero());  // used: resize keeps it
  p.resize(n);
  p.use_pore_water_fields();  // the saturated transfer's fields, used too
  for (std::size_t k = 0; k < n; ++k) p.id[k] = static_cast<std::int64_t>(10 + k);
  std::size_t f = 0;
  for_each_field(particle_fields, [&](const auto& field) {
    auto& column = field.of(p);
    using Column = std::remove_cvref_t<decltype(column)>;
    for (std::size_t k = 0; k < n; ++k) {
      const std::int64_t id = p.id[k];
      if constexpr (std::is_same_v<Column, SurfaceStresses>) {
        for (std::size_t s = 0; s < 3; ++s)
          column.values[3 * k + s] = Vec4::Constant(planted(f, id, s));
      } else if (static_cast<const void*>(&column) != static_cast<const void*>(&p.id)) {
        column[k] = planted_entry<typename Column::value_type>(f, id);
      }
    }
    ++f;
  });
  // Inside a 10 × 10 grid of unit cells, in a reverse order of cells; sizes and
  // materials as the checkpoint's checks want them.
  for (std::size_t k = 0; k < n; ++k) {
    const double c = static_cast<double>((n - 1 - k) % 50);
    p.coordinates[k] = Vec2(0.5 + std::fmod(c, 10.0), 0.5 + std::floor(c / 10.0));
    p.size[k] = Vec2(0.5, 0.5 + 0.001 * static_cast<double>(k));
    p.material_id[k] = static_cast<std::int32_t>(k % 2);
    p.liquefied[k] = static_cast<std::int64_t>((k / 2) % 2);  // a flag: 0 or 1
  }
  return p;
}

/// Failures of every field whose values are not those planted for its particle's id.
std::vector<std::string> misplaced(const Particles& p, const Particles& original) {
  std::map<std::int64_t, std::size_t> row_of;
  for (std::size_t k = 0; k < original.count(); ++k) row_of[original.id[k]] = k;
  std::vector<std::string> failures;
  for_each_field(particle_fields, [&](const auto& field) {
    const auto& column = field.of(p);
    const auto& expected = field.of(original);
    using Column = std::remove_cvref_t<decltype(column)>;
    for (std::size_t k = 0; k < p.count(); ++k) {
      const std::size_t r = row_of.at(p.id[k]);
      bool ok = true;
      if constexpr (std::is_same_v<Column, SurfaceStresses>) {
        const auto a = column.of(k), b = expected.of(r);
        ok = a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin());
      } else {
        ok = same(column[k], expected[r]);
      }
      if (!ok) {
        failures.push_back(std::string(field.name) + " of id " + std::to_string(p.id[k]));
        return;
      }
    }
  });
  return failures;
}

TEST(ParticleFieldTable, EveryFieldFollowsItsParticleThroughTheSort) {
  const Particles original = planted_particles(200);
  Particles p = original;
  mpm::GridGeometry grid = mpm::GridGeometry::covering(Vec2(0, 0), Vec2(10, 10), 1.0);
  mpm::sort_particles_by_cell(p, p.count(), grid);
  EXPECT_NE(p.id, original.id);  // the sort did reorder
  EXPECT_EQ(misplaced(p, original), std::vector<std::string>{});
  p.check_consistent_sizes();
}

TEST(RowCycles, MovesEveryRowToWhereThePermutationSays) {
  // Row k takes old row order[k]: the identity, one swap, one cycle through every row,
  // and shuffles (short and long cycles, fixed rows among them), against a plain gather.
  std::mt19937 random(7);
  std::vector<std::vector<std::uint32_t>> orders = {{0, 1, 2, 3}, {1, 0, 2, 3}, {1, 2, 3, 0}};
  for (const std::size_t n : {2u, 17u, 1000u}) {
    std::vector<std::uint32_t> order(n);
    std::iota(order.begin(), order.end(), 0u);
    std::shuffle(order.begin(), order.end(), random);
    orders.push_back(order);
  }
  for (std::vector<std::uint32_t> order : orders) {
    const std::size_t n = order.size();
    std::vector<double> column(n);
    for (std::size_t k = 0; k < n; ++k) column[k] = 0.5 + static_cast<double>(k);
    SurfaceStresses surfaces{2, std::vector<Vec4>(2 * n)};
    for (std::size_t k = 0; k < 2 * n; ++k) surfaces.values[k] = Vec4::Constant(double(k));
    std::vector<double> expected(n);
    for (std::size_t k = 0; k < n; ++k) expected[k] = column[order[k]];
    std::vector<Vec4> expected_surfaces(2 * n);
    for (std::size_t k = 0; k < 2 * n; ++k)
      expected_surfaces[k] = surfaces.values[2 * order[k / 2] + k % 2];
    const RowCycles cycles(order);
    cycles.apply(column);
    cycles.apply(surfaces);
    EXPECT_EQ(column, expected);
    EXPECT_EQ(surfaces.values, expected_surfaces);
    for (std::size_t k = 0; k < n; ++k) ASSERT_EQ(order[k], k);  // marked done
  }
}

TEST(ParticleFieldTable, ResizeKeepsEveryFieldAndFillsNewRows) {
  const Particles original = planted_particles(20);
  Particles p = original;
  p.resize(25);
  p.check_consistent_sizes();
  EXPECT_EQ(p.element[24], -1);  // the table's fill for element: no source element
  EXPECT_EQ(p.mass[24], 0.0);
  EXPECT_EQ(p.surface_stress.values.size(), 25U * 3U);
  p.resize(20);
  p.shrink_to_fit();
  EXPECT_EQ(misplaced(p, original), std::vector<std::string>{});
  EXPECT_EQ(p.bytes(), original.bytes());
}

TEST(ParticleFieldTable, AWrongSizedFieldIsNamed) {
  std::vector<std::string> named;
  for_each_field(particle_fields, [&](const auto& field) {
    Particles p = planted_particles(5);
    auto& column = field.of(p);
    if constexpr (std::is_same_v<std::remove_cvref_t<decltype(column)>, SurfaceStresses>) {
      column.values.resize(column.values.size() - 3);  // one point of 3 surfaces fewer
    } else {
      column.pop_back();
    }
    // The coordinates define the count.
    if (static_cast<const void*>(&column) == static_cast<const void*>(&p.coordinates)) return;
    try {
      p.check_consistent_sizes();
    } catch (const Error& e) {
      if (std::string(e.what()).find(std::string(field.name)) != std::string::npos)
        named.push_back(std::string(field.name));
    }
  });
  EXPECT_EQ(named.size(), std::tuple_size_v<ParticleFieldTable> - 1);
}

TEST(ParticleFieldTable, EveryFieldCrossesBetweenRanksInItsPackedRow) {
  const Particles original = planted_particles(30);
  const mpm::PackedLayout layout{3, true, true};
  std::vector<std::size_t> rows(original.count());
  std::iota(rows.rbegin(), rows.rend(), std::size_t{0});  // reversed
  std::vector<std::byte> bytes;
  mpm::pack_particles(original, rows, layout, bytes);
  Particles received;
  received.surface_stress.per_point = 3;
  received.affine_velocity.assign(1, Vec4::Zero());
  received.resize(0);
  ASSERT_EQ(mpm::unpack_particles(bytes, layout, received), original.count());
  EXPECT_EQ(received.id.front(), original.id.back());
  EXPECT_EQ(misplaced(received, original), std::vector<std::string>{});
  // The row's size is the table's: every field's entry, the surfaces, the affine one and
  // the saturated transfer's.
  std::size_t expected = 0;
  for_each_field(particle_fields, [&](const auto& field) {
    const auto& column = field.of(original);
    using Column = std::remove_cvref_t<decltype(column)>;
    if constexpr (std::is_same_v<Column, SurfaceStresses>) {
      expected += 3 * sizeof(Vec4);
    } else {
      expected += sizeof(typename Column::value_type);
    }
  });
  EXPECT_EQ(layout.bytes(), expected);
}

TEST(ParticleFieldTable, EveryFieldGoesThroughTheCheckpoint) {
  ParticleCheckpoint c;
  c.header.kind = CheckpointKind::mpm;
  c.header.case_name = "fields";
  const Material soil = synthetic::soil(MaterialModel::mohr_coulomb);
  c.materials = {soil, soil};
  c.materials[1].name = "other";
  c.particles = planted_particles(40);  // within the schema's magnitudes and signs
  const auto folder = std::filesystem::path(SLIDE_BINARY_DIR) / "test-scratch" / "field-tables";
  std::filesystem::create_directories(folder);
  write_checkpoint(folder / "all.h5", c);
  const ParticleCheckpoint back = read_particle_checkpoint(folder / "all.h5");
  EXPECT_EQ(misplaced(back.particles, c.particles), std::vector<std::string>{});
}

// ----------------------------------------------------------------------------- schema page

/// The rows of the schema page's table under `heading`: dataset → units.
std::map<std::string, std::string> schema_rows(const std::string& heading) {
  std::ifstream file(std::filesystem::path(SLIDE_SOURCE_DIR) / "common/io/checkpoint-schema.md");
  std::string line;
  bool in_section = false;
  std::map<std::string, std::string> rows;
  const std::regex row(R"(^\| `([^`]+)` \| [^|]+ \| [^|]+ \| ([^|]+) \|)");
  while (std::getline(file, line)) {
    if (line.rfind("#", 0) == 0) in_section = line.find(heading) != std::string::npos;
    std::smatch m;
    if (in_section && std::regex_search(line, m, row)) {
      std::string units = m[2];
      units.erase(units.find_last_not_of(' ') + 1);
      rows[m[1]] = units;
    }
  }
  return rows;
}

/// The datasets a table's fields of rows `kind` make, with their units.
template <class Table>
std::map<std::string, std::string> table_datasets(const Table& table, RowKind kind) {
  std::map<std::string, std::string> datasets;
  for_each_field(table, [&](const auto& field) {
    if (field.rows != kind) return;
    using Column = typename std::remove_cvref_t<decltype(field)>::column_type;
    if constexpr (std::is_same_v<Column, std::vector<MaterialState>>) {
      for (const StateField& member : material_state_fields) {
        datasets[std::string(field.name) + "/" + std::string(member.name)] =
            std::string(member.unit);
      }
    } else {
      datasets[std::string(field.name)] = std::string(field.unit);
    }
  });
  return datasets;
}

TEST(FieldTables, TheSchemaPageListsEveryFieldWithItsUnit) {
  // Particles are their fields, no more, no less.
  EXPECT_EQ(schema_rows("### `/particles`"), table_datasets(particle_fields, RowKind::particle));
  // The FE groups also hold what the mesh and the state derive (coordinates, quality,
  // quadrature): the state's fields must be among their rows, with their units.
  for (const auto& [kind, heading] :
       {std::pair{RowKind::node, "### `/nodes`"}, std::pair{RowKind::element, "### `/elements`"},
        std::pair{RowKind::gauss_point, "### `/gauss_points`"}}) {
    const auto page = schema_rows(heading);
    for (const auto& [dataset, units] : table_datasets(fe_fields, kind)) {
      ASSERT_TRUE(page.contains(dataset)) << heading << " lacks " << dataset;
      EXPECT_EQ(page.at(dataset), units) << heading << " " << dataset;
    }
  }
}

}  // namespace
}  // namespace slide
