// Pure-MPM particles: the per-cell Gauss–Legendre layout inside the body's mesh, and the
// surface heights of the K0 stresses.
#include <gtest/gtest.h>

#include "common/base/error.hpp"
#include "tests/support/mpm_builders.hpp"

namespace slide::mpm {
namespace {

using namespace testing;

/// A 20 m × 20 m square block of one quad.
Mesh square_mesh() {
  Mesh mesh;
  mesh.element_type = ElementType::quad4_2x2;
  mesh.nodes = {Vec2(0, 0), Vec2(20, 0), Vec2(20, 20), Vec2(0, 20)};
  mesh.connectivity = {0, 1, 2, 3};
  mesh.material_id = {0};
  return mesh;
}

/// A 20 m high crest block (0–20 m) and its 1H:1V face (20–40 m), as three triangles.
Mesh sloped_mesh() {
  Mesh mesh;
  mesh.element_type = ElementType::tri3;
  mesh.nodes = {Vec2(0, 0), Vec2(20, 0), Vec2(40, 0), Vec2(0, 20), Vec2(20, 20)};
  mesh.connectivity = {0, 1, 4, 0, 4, 3, 1, 2, 4};
  mesh.material_id = {0, 0, 0};
  return mesh;
}

TEST(ParticleGeneration, GaussLayoutFillsWholeCellsExactly) {
  MpmSettings s = settings_on(Vec2(0, 0), Vec2(40, 30), 1.0);
  const MaterialTable materials{elastic_soil()};
  const Mesh mesh = square_mesh();
  const Particles p = generate_mesh_particles(s.grid, mesh, 4, 4, materials);
  EXPECT_EQ(p.count(), 20u * 20u * 16u);
  double volume = 0.0, mass = 0.0;
  for (std::size_t k = 0; k < p.count(); ++k) {
    volume += p.volume[k];
    mass += p.mass[k];
    EXPECT_EQ(p.element[k], -1);
    EXPECT_EQ(p.size[k], Vec2(0.25, 0.25));
  }
  EXPECT_NEAR(volume, 400.0, 1e-9);
  EXPECT_NEAR(mass, 1700.0 * 400.0, 1e-6);
}

// Each MPI rank makes its part of the body (a Part): the parts, joined in order, are the
// whole body row for row, ids included, and each knows the whole count.
TEST(ParticleGeneration, PartsJoinToTheWholeBody) {
  MpmSettings s = settings_on(Vec2(0, 0), Vec2(60, 30), 1.0);
  const MaterialTable materials{elastic_soil()};
  const Mesh mesh = sloped_mesh();
  const Particles whole = generate_mesh_particles(s.grid, mesh, 2, 2, materials);
  for (int parts : {1, 2, 3, 7}) {
    std::vector<std::int64_t> ids;
    std::vector<Vec2> coordinates;
    for (int k = 0; k < parts; ++k) {
      std::size_t count = 0;
      const Particles part =
          generate_mesh_particles(s.grid, mesh, 2, 2, materials, {k, parts}, &count);
      EXPECT_EQ(count, whole.count());
      ids.insert(ids.end(), part.id.begin(), part.id.end());
      coordinates.insert(coordinates.end(), part.coordinates.begin(), part.coordinates.end());
    }
    EXPECT_EQ(ids, whole.id) << parts << " parts";
    EXPECT_EQ(coordinates, whole.coordinates) << parts << " parts";
  }
  EXPECT_THROW(generate_mesh_particles(s.grid, mesh, 2, 2, materials, {3, 3}), Error);
}

TEST(ParticleGeneration, SlopedFaceAndSurfaceHeights) {
  MpmSettings s = settings_on(Vec2(0, 0), Vec2(60, 30), 1.0);
  const MaterialTable materials{elastic_soil()};
  const Mesh mesh = sloped_mesh();
  const Particles p = generate_mesh_particles(s.grid, mesh, 2, 2, materials);
  double volume = 0.0;
  for (double v : p.volume) volume += v;
  // 600 m² of body; the face cuts cells, so the kept Gauss points approximate it.
  EXPECT_NEAR(volume, 600.0, 600.0 * 0.02);
  const std::vector<Vec2> points{Vec2(5, 3), Vec2(25, 1), Vec2(39.5, 0.2)};
  const auto heights = mesh_surface_heights(mesh, points);
  EXPECT_NEAR(heights[0], 20.0, 1e-12);
  EXPECT_NEAR(heights[1], 15.0, 1e-12);
  EXPECT_NEAR(heights[2], 0.5, 1e-12);
  for (const Vec2& x : p.coordinates) EXPECT_LT(x.y(), 40.0 - x.x() + 1e-12);
}

TEST(ParticleGeneration, K0StressesOfLevelGround) {
  Particles p;
  p.resize(1);
  p.coordinates[0] = Vec2(3, 4);
  const MaterialTable materials{elastic_soil()};
  apply_k0_stresses(p, materials, std::vector<double>{10.0}, 9.81);
  const double syy = -1700.0 * 9.81 * 6.0;
  const double k0 = 0.23 / 0.77;
  EXPECT_NEAR(p.stress[0][1], syy, 1e-9);
  EXPECT_NEAR(p.stress[0][0], k0 * syy, 1e-9);
  EXPECT_NEAR(p.stress[0][2], k0 * syy, 1e-9);
  EXPECT_EQ(p.stress[0][3], 0.0);
}

}  // namespace
}  // namespace slide::mpm
