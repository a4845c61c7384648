// The structured mesh generators (profile, blocks), their tri3 variants, the boundary
// node sets, mesh validation and build_mesh's checks, on the geometries of docs/method.md §7.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "common/base/error.hpp"
#include "common/input/mesh_generation.hpp"
#include "tests/support/errors.hpp"

namespace slide {
namespace {

MaterialTable one_soil() {
  Material soil;
  soil.name = "soil";
  return {soil};
}

MeshSpec profile_spec(std::vector<Vec2> surface, double h, ElementType type) {
  MeshSpec spec;
  spec.generator = MeshGenerator::profile;
  spec.element_type = type;
  spec.element_size = h;
  spec.surface = std::move(surface);
  spec.material = "soil";
  return spec;
}

MeshBlock block(Vec2 p0, Vec2 p1, Vec2 p2, Vec2 p3, int nu, int nv) {
  return MeshBlock{{p0, p1, p2, p3}, nu, nv, "soil"};
}

// slope-frictional (docs/method.md §7) as blocks: the rectangle under the crest, and the
// triangle under the 1H:1V face split into three quads through its centroid.
MeshSpec slope_frictional_blocks(ElementType type) {
  const Vec2 c(80.0 / 3.0, 20.0 / 3.0);
  MeshSpec spec;
  spec.generator = MeshGenerator::blocks;
  spec.element_type = type;
  spec.blocks = {
      block({0, 0}, {20, 0}, {20, 20}, {0, 20}, 20, 20),
      block({20, 0}, {30, 0}, c, {20, 10}, 10, 10),
      block({30, 0}, {40, 0}, {30, 10}, c, 10, 10),
      block({20, 10}, c, {30, 10}, {20, 20}, 10, 10),
  };
  return spec;
}

double total_area(const Mesh& mesh) {
  double area = 0.0;
  for (Index e = 0; e < mesh.element_count(); ++e) {
    area += element_area(mesh.shape(), mesh.element_nodes(e, mesh.nodes));
  }
  return area;
}

/// The smallest det J over every corner of every element (signed area for triangles).
double smallest_corner_jacobian(const Mesh& mesh) {
  double smallest = INFINITY;
  for (Index e = 0; e < mesh.element_count(); ++e) {
    const ElementNodes x = mesh.element_nodes(e, mesh.nodes);
    if (mesh.shape() == ElementShape::tri3) {
      smallest = std::min(smallest, element_area(ElementShape::tri3, x));
      continue;
    }
    for (const Vec2& xi : {Vec2(-1, -1), Vec2(1, -1), Vec2(1, 1), Vec2(-1, 1)}) {
      smallest = std::min(smallest, jacobian(ElementShape::quad4, x, xi).determinant());
    }
  }
  return smallest;
}

/// Indices of the nodes satisfying `predicate`, increasing.
template <typename Predicate>
std::vector<Index> nodes_where(const Mesh& mesh, Predicate predicate) {
  std::vector<Index> result;
  for (Index i = 0; i < mesh.node_count(); ++i) {
    if (predicate(mesh.nodes[static_cast<std::size_t>(i)])) result.push_back(i);
  }
  return result;
}

void expect_boundary_sets(const Mesh& mesh, double x_max, std::size_t left, std::size_t right,
                          std::size_t base) {
  ASSERT_EQ(mesh.node_sets.size(), 3U);
  const NodeSet* l = mesh.find_node_set("left");
  const NodeSet* r = mesh.find_node_set("right");
  const NodeSet* b = mesh.find_node_set("base");
  ASSERT_NE(l, nullptr);
  ASSERT_NE(r, nullptr);
  ASSERT_NE(b, nullptr);
  EXPECT_EQ(l->nodes, nodes_where(mesh, [](const Vec2& p) { return p.x() == 0.0; }));
  EXPECT_EQ(r->nodes, nodes_where(mesh, [&](const Vec2& p) { return p.x() == x_max; }));
  EXPECT_EQ(b->nodes, nodes_where(mesh, [](const Vec2& p) { return p.y() == 0.0; }));
  EXPECT_EQ(l->nodes.size(), left);
  EXPECT_EQ(r->nodes.size(), right);
  EXPECT_EQ(b->nodes.size(), base);
  EXPECT_EQ(l->normal, Vec2(-1.0, 0.0));
  EXPECT_EQ(r->normal, Vec2(1.0, 0.0));
  EXPECT_EQ(b->normal, Vec2(0.0, -1.0));
}

using testing::error_of;

// ---------------------------------------------------------------------------- profile

TEST(ProfileMesh, ColumnShortIs50By40UnitQuads) {
  const Mesh mesh =
      generate_profile_mesh(profile_spec({{0, 40}, {50, 40}}, 1.0, ElementType::quad4_1gp), 0);
  EXPECT_EQ(mesh.element_type, ElementType::quad4_1gp);
  EXPECT_EQ(mesh.element_count(), 50 * 40);
  EXPECT_EQ(mesh.node_count(), 51 * 41);
  EXPECT_NEAR(total_area(mesh), 2000.0, 2000.0 * 1e-12);
  // Every element is the unit square: det J = 1/4 at every corner (the shoelace area
  // loses a few ulps to the large coordinates).
  EXPECT_DOUBLE_EQ(smallest_corner_jacobian(mesh), 0.25);
  for (Index e = 0; e < mesh.element_count(); ++e) {
    EXPECT_NEAR(element_area(mesh.shape(), mesh.element_nodes(e, mesh.nodes)), 1.0, 1e-12);
  }
  // Nodes row by row from the base, x fastest; elements counter-clockwise from the
  // lower-left node.
  EXPECT_EQ(mesh.nodes[52], Vec2(1.0, 1.0));
  const std::vector<Index> first(mesh.element(0).begin(), mesh.element(0).end());
  EXPECT_EQ(first, (std::vector<Index>{0, 1, 52, 51}));
  expect_boundary_sets(mesh, 50.0, 41, 41, 51);
  EXPECT_TRUE(std::all_of(mesh.material_id.begin(), mesh.material_id.end(),
                          [](std::int32_t m) { return m == 0; }));
  EXPECT_NO_THROW(validate_mesh(mesh, "column", 1));
}

TEST(ProfileMesh, SlopeCohesiveFollowsEverySurfaceKink) {
  const std::vector<Vec2> surface{{0, 15}, {20, 15}, {50, 5}, {120, 5}};
  const Mesh mesh = generate_profile_mesh(profile_spec(surface, 1.0, ElementType::quad4_2x2), 0);
  EXPECT_EQ(mesh.element_count(), 120 * 15);
  EXPECT_EQ(mesh.node_count(), 121 * 16);
  // 20·15 + 30·(15 + 5)/2 + 70·5
  EXPECT_NEAR(total_area(mesh), 950.0, 950.0 * 1e-12);
  EXPECT_GT(smallest_corner_jacobian(mesh), 0.0);
  // Node j of column i sits at y = j/15 · y_surface(x_i); the kinks are columns 20, 50.
  const auto node = [&](int i, int j) { return mesh.nodes[static_cast<std::size_t>(j * 121 + i)]; };
  EXPECT_EQ(node(20, 15), Vec2(20.0, 15.0));
  EXPECT_EQ(node(50, 15), Vec2(50.0, 5.0));
  EXPECT_EQ(node(120, 15), Vec2(120.0, 5.0));
  EXPECT_NEAR(node(35, 15).y(), 10.0, 1e-12);
  EXPECT_NEAR(node(35, 6).y(), 6.0 / 15.0 * 10.0, 1e-12);
  EXPECT_NEAR(node(80, 3).y(), 1.0, 1e-12);
  expect_boundary_sets(mesh, 120.0, 16, 16, 121);
  EXPECT_NO_THROW(validate_mesh(mesh, "slope-cohesive", 1));
}

TEST(ProfileMesh, ColumnsAndRowsRoundToTheElementSize) {
  // Segments 0–10 (h = 3: round(3.33) = 3 columns) and 10–11 (round(0.33) → at least 1);
  // rows round(7/3) = 2.
  const Mesh mesh = generate_profile_mesh(
      profile_spec({{0, 7}, {10, 7}, {11, 6}}, 3.0, ElementType::quad4_1gp), 0);
  EXPECT_EQ(mesh.element_count(), 4 * 2);
  EXPECT_EQ(mesh.node_count(), 5 * 3);
  EXPECT_NEAR(total_area(mesh), 70.0 + 6.5, 76.5 * 1e-12);
  EXPECT_NEAR(mesh.nodes[1].x(), 10.0 / 3.0, 1e-12);
}

TEST(ProfileMesh, Tri3SplitsEveryQuadWithAlternatingDiagonals) {
  const std::vector<Vec2> surface{{0, 15}, {20, 15}, {50, 5}, {120, 5}};
  const Mesh mesh = generate_profile_mesh(profile_spec(surface, 1.0, ElementType::tri3), 0);
  EXPECT_EQ(mesh.element_count(), 2 * 120 * 15);
  EXPECT_EQ(mesh.node_count(), 121 * 16);
  EXPECT_NEAR(total_area(mesh), 950.0, 950.0 * 1e-12);
  EXPECT_GT(smallest_corner_jacobian(mesh), 0.0);
  // Cell (0, 0), even: diagonal a–c; cell (1, 0), odd: diagonal b–d.
  const auto triangle = [&](Index e) {
    return std::vector<Index>(mesh.element(e).begin(), mesh.element(e).end());
  };
  EXPECT_EQ(triangle(0), (std::vector<Index>{0, 1, 122}));
  EXPECT_EQ(triangle(1), (std::vector<Index>{0, 122, 121}));
  EXPECT_EQ(triangle(2), (std::vector<Index>{1, 2, 122}));
  EXPECT_EQ(triangle(3), (std::vector<Index>{2, 123, 122}));
  // Cell (0, 1) is odd again.
  EXPECT_EQ(triangle(240), (std::vector<Index>{121, 122, 242}));
  expect_boundary_sets(mesh, 120.0, 16, 16, 121);
  EXPECT_NO_THROW(validate_mesh(mesh, "slope-cohesive tri3", 1));
}

TEST(ProfileMesh, RejectsImpossibleSurfaces) {
  const auto message = [](std::vector<Vec2> surface, double h = 1.0) {
    return error_of([&] {
      generate_profile_mesh(profile_spec(std::move(surface), h, ElementType::quad4_1gp), 0);
    });
  };
  EXPECT_EQ(message({{1, 5}, {4, 5}}),
            "mesh.surface[0] = [1, 5] (the surface starts at the wall x = 0)");
  EXPECT_EQ(message({{0, 5}, {4, 5}, {4, 2}}),
            "mesh.surface[2]: x = 4 is not greater than the previous point's x = 4");
  EXPECT_EQ(message({{0, 5}, {4, 0}}), "mesh.surface[1]: y = 0 is not above the base y = 0");
  EXPECT_EQ(message({{0, 5}}),
            "mesh.surface has 1 point(s) (expected at least 2, from the wall x = 0)");
  EXPECT_EQ(message({{0, 5}, {4, 5}}, 0.0),
            "mesh.element_size = 0 is not admissible (expected > 0 m)");
}

// ---------------------------------------------------------------------------- blocks

TEST(BlockMesh, SlopeFrictionalMergesSharedEdges) {
  const Mesh mesh =
      generate_block_mesh(slope_frictional_blocks(ElementType::quad4_1gp), one_soil());
  EXPECT_EQ(mesh.element_count(), 400 + 3 * 100);
  // 441 + 3·121 grid nodes, 53 of them repeats on the five shared edges (V − E + F = 1
  // with 1450 edges, 100 of them on the boundary, agrees).
  EXPECT_EQ(mesh.node_count(), 751);
  EXPECT_NEAR(total_area(mesh), 600.0, 600.0 * 1e-12);
  EXPECT_GT(smallest_corner_jacobian(mesh), 0.0);
  // The face reaches the base: "right" (x = 40) is the single toe node.
  expect_boundary_sets(mesh, 40.0, 21, 1, 41);
  EXPECT_EQ(mesh.nodes[static_cast<std::size_t>(mesh.find_node_set("right")->nodes[0])],
            Vec2(40.0, 0.0));
  // No two nodes coincide after merging.
  double closest = INFINITY;
  for (std::size_t i = 0; i < mesh.nodes.size(); ++i) {
    for (std::size_t j = i + 1; j < mesh.nodes.size(); ++j) {
      closest = std::min(closest, (mesh.nodes[i] - mesh.nodes[j]).norm());
    }
  }
  double shortest_edge = INFINITY;
  for (Index e = 0; e < mesh.element_count(); ++e) {
    const ElementNodes x = mesh.element_nodes(e, mesh.nodes);
    for (int k = 0; k < 4; ++k)
      shortest_edge = std::min(shortest_edge, (x.row((k + 1) % 4) - x.row(k)).norm());
  }
  // No two nodes are closer than the shortest element edge, √2/3 m (a cell of the
  // centroid quads): merging left no duplicates.
  EXPECT_NEAR(shortest_edge, std::sqrt(2.0) / 3.0, 1e-12);
  EXPECT_DOUBLE_EQ(closest, shortest_edge);
  // Numbering: block 0 first, row by row; block 1 starts with its first new node (31, 0)
  // after reusing (20, 0) = node 20.
  EXPECT_EQ(mesh.nodes[20], Vec2(20.0, 0.0));
  EXPECT_EQ(mesh.nodes[441], Vec2(21.0, 0.0));
  EXPECT_EQ(mesh.element(400)[0], 20);
  EXPECT_NO_THROW(validate_mesh(mesh, "slope-frictional", 1));
}

TEST(BlockMesh, SlopeFrictionalTri3) {
  const Mesh mesh = generate_block_mesh(slope_frictional_blocks(ElementType::tri3), one_soil());
  EXPECT_EQ(mesh.element_type, ElementType::tri3);
  EXPECT_EQ(mesh.element_count(), 2 * 700);
  EXPECT_EQ(mesh.node_count(), 751);
  EXPECT_NEAR(total_area(mesh), 600.0, 600.0 * 1e-12);
  EXPECT_GT(smallest_corner_jacobian(mesh), 0.0);
  expect_boundary_sets(mesh, 40.0, 21, 1, 41);
  EXPECT_NO_THROW(validate_mesh(mesh, "slope-frictional tri3", 1));
}

TEST(BlockMesh, MaterialIdsComeFromTheBlocks) {
  MaterialTable materials = one_soil();
  materials.push_back(materials[0]);
  materials[1].name = "rock";
  MeshSpec spec;
  spec.generator = MeshGenerator::blocks;
  spec.blocks = {block({0, 0}, {2, 0}, {2, 1}, {0, 1}, 2, 1),
                 block({0, 1}, {2, 1}, {2, 3}, {0, 3}, 2, 2)};
  spec.blocks[0].material = "rock";
  const Mesh mesh = generate_block_mesh(spec, materials);
  EXPECT_EQ(mesh.material_id, (std::vector<std::int32_t>{1, 1, 0, 0, 0, 0}));
  EXPECT_EQ(mesh.node_count(), 3 * 4);

  spec.blocks[1].material = "clay";
  EXPECT_EQ(error_of([&] { generate_block_mesh(spec, materials); }),
            "mesh.blocks[1].material: unknown material \"clay\" (materials of the case: soil, "
            "rock)");
}

TEST(BlockMesh, RejectsHangingNodes) {
  // Two unit squares sharing x = 1, with 2 and 3 cells along it.
  MeshSpec spec;
  spec.generator = MeshGenerator::blocks;
  spec.blocks = {block({0, 0}, {1, 0}, {1, 1}, {0, 1}, 2, 2),
                 block({1, 0}, {2, 0}, {2, 1}, {1, 1}, 3, 3)};
  const std::string message = error_of([&] { generate_block_mesh(spec, one_soil()); });
  EXPECT_EQ(message.rfind("mesh.blocks[0] and mesh.blocks[1]: hanging node at (1, 0.5)", 0), 0U)
      << message;

  // A block whose edge spans two blocks is non-conforming too (a T-junction).
  spec.blocks = {block({0, 0}, {1, 0}, {1, 1}, {0, 1}, 1, 1),
                 block({0, 1}, {1, 1}, {1, 2}, {0, 2}, 1, 1),
                 block({1, 0}, {2, 0}, {2, 2}, {1, 2}, 1, 1)};
  const std::string t_junction = error_of([&] { generate_block_mesh(spec, one_soil()); });
  EXPECT_NE(t_junction.find("mesh.blocks[0] and mesh.blocks[2]: hanging node at (1, 1)"),
            std::string::npos)
      << t_junction;
}

TEST(BlockMesh, RejectsClockwiseCornersAndEmptyBlocks) {
  MeshSpec spec;
  spec.generator = MeshGenerator::blocks;
  spec.blocks = {block({0, 0}, {0, 1}, {1, 1}, {1, 0}, 1, 1)};
  EXPECT_NE(error_of([&] { generate_block_mesh(spec, one_soil()); })
                .find("mesh.blocks[0]: corners (0, 0) (0, 1) (1, 1) (1, 0) are not "
                      "counter-clockwise"),
            std::string::npos);
  spec.blocks = {block({0, 0}, {1, 0}, {1, 1}, {0, 1}, 0, 1)};
  EXPECT_EQ(error_of([&] { generate_block_mesh(spec, one_soil()); }),
            "mesh.blocks[0]: cells = [0, 1] (expected at least one cell each way)");
}

// ---------------------------------------------------------------------------- validation

Mesh unit_square_mesh() {
  Mesh mesh;
  mesh.element_type = ElementType::quad4_1gp;
  mesh.nodes = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  mesh.connectivity = {0, 1, 2, 3};
  mesh.material_id = {0};
  mesh.node_sets = {NodeSet{"base", {0, 1}, Vec2(0, -1)}};
  return mesh;
}

TEST(ValidateMesh, AcceptsAGoodMeshAndNamesEachFault) {
  EXPECT_NO_THROW(validate_mesh(unit_square_mesh(), "m", 1));

  Mesh clockwise = unit_square_mesh();
  clockwise.connectivity = {0, 3, 2, 1};
  EXPECT_EQ(error_of([&] { validate_mesh(clockwise, "m.msh", 1); }),
            "m.msh: element 0 at (0.5, 0.5) is inverted or has zero area: det J = -0.25 at its "
            "corner 0 (node 0 at (0, 0))");

  Mesh dart = unit_square_mesh();  // positive area, reflex corner 2
  dart.nodes[2] = Vec2(0.3, 0.3);
  EXPECT_NE(error_of([&] { validate_mesh(dart, "m", 1); }).find("inverted or has zero area"),
            std::string::npos);
  EXPECT_NE(error_of([&] { validate_mesh(dart, "m", 1); }).find("corner 2 (node 2 at (0.3, 0.3))"),
            std::string::npos);

  Mesh collapsed = unit_square_mesh();
  collapsed.nodes[2] = Vec2(1, 0);
  EXPECT_NE(error_of([&] { validate_mesh(collapsed, "m", 1); }).find("det J = 0 at its corner 1"),
            std::string::npos);

  Mesh triangle;
  triangle.element_type = ElementType::tri3;
  triangle.nodes = {{0, 0}, {1, 0}, {2, 0}};
  triangle.connectivity = {0, 1, 2};
  triangle.material_id = {0};
  EXPECT_EQ(error_of([&] { validate_mesh(triangle, "t", 1); }),
            "t: element 0 at (1, 0) is inverted or has zero area (signed area 0 m²)");

  Mesh lonely = unit_square_mesh();
  lonely.nodes.push_back(Vec2(3, 4));
  EXPECT_EQ(error_of([&] { validate_mesh(lonely, "m", 1); }),
            "m: node 4 at (3, 4) belongs to no element");

  Mesh material = unit_square_mesh();
  material.material_id = {2};
  EXPECT_EQ(error_of([&] { validate_mesh(material, "m", 2); }),
            "m: element 0 at (0.5, 0.5) has material id 2, out of range (the case has 2 "
            "materials)");

  Mesh empty_set = unit_square_mesh();
  empty_set.node_sets.push_back(NodeSet{"toe", {}, Vec2(1, 0)});
  EXPECT_EQ(error_of([&] { validate_mesh(empty_set, "m", 1); }), "m: node set 'toe' is empty");

  Mesh out_of_range = unit_square_mesh();
  out_of_range.node_sets[0].nodes.push_back(7);
  EXPECT_EQ(error_of([&] { validate_mesh(out_of_range, "m", 1); }),
            "m: node set 'base' refers to node 7, out of range (the mesh has 4 nodes)");

  Mesh bent = unit_square_mesh();
  bent.node_sets[0].nodes.push_back(2);
  EXPECT_NE(error_of([&] { validate_mesh(bent, "m", 1); }).find("node set 'base' is not straight"),
            std::string::npos);

  Mesh bad_node = unit_square_mesh();
  bad_node.connectivity[3] = 9;
  EXPECT_EQ(error_of([&] { validate_mesh(bad_node, "m", 1); }),
            "m: element 0 refers to node 9, out of range (the mesh has 4 nodes)");
}

// ---------------------------------------------------------------------------- build_mesh

Case column_case() {
  Case c;
  c.file = "cases/column-short/case.toml";
  c.materials = one_soil();
  c.mesh = profile_spec({{0, 40}, {50, 40}}, 1.0, ElementType::quad4_1gp);
  c.mpm.domain_min = Vec2(0.0, 0.0);  // column-short's grid, which build_mesh checks
  c.mpm.domain_max = Vec2(200.0, 45.0);
  c.fem.geostatic_boundaries = {{"left", BoundaryCondition::roller},
                                {"right", BoundaryCondition::roller},
                                {"base", BoundaryCondition::roller}};
  c.fem.failure_boundaries = {{"left", BoundaryCondition::roller},
                              {"right", BoundaryCondition::free},
                              {"base", BoundaryCondition::friction}};
  return c;
}

TEST(BuildMesh, GeneratesTheCaseMesh) {
  const Mesh mesh = build_mesh(column_case());
  EXPECT_EQ(mesh.element_count(), 2000);
  EXPECT_EQ(mesh.node_count(), 2091);

  Case slope = column_case();
  slope.mesh = slope_frictional_blocks(ElementType::quad4_1gp);
  EXPECT_EQ(build_mesh(slope).node_count(), 751);
}

TEST(BuildMesh, RejectsBoundariesTheMeshDoesNotHave) {
  Case c = column_case();
  c.fem.failure_boundaries["toe"] = BoundaryCondition::fixed;
  EXPECT_EQ(error_of([&] { build_mesh(c); }),
            "cases/column-short/case.toml: boundary 'toe' used in fem.failure.boundaries is not "
            "a node set of the generated mesh (left, right, base)");
}

TEST(BuildMesh, PrefixesGeneratorErrorsWithTheCaseFile) {
  Case c = column_case();
  c.mesh.material = "clay";
  EXPECT_EQ(error_of([&] { build_mesh(c); }),
            "cases/column-short/case.toml: mesh.material: unknown material \"clay\" (materials "
            "of the case: soil)");
  c = column_case();
  c.mesh.surface[1].y() = -1.0;
  EXPECT_EQ(error_of([&] { build_mesh(c); }),
            "cases/column-short/case.toml: mesh.surface[1]: y = -1 is not above the base y = 0");
}

// An element size that asks for more elements than the mesher builds (a typing or unit
// error: 1e-300 m over 50 m × 40 m is 2·10⁶⁰³ elements) is refused naming the key; before,
// the column count overflowed and the run went on with a single element.
TEST(ProfileMesh, AnElementSizeThatAsksForMoreThanTenMillionElementsIsRefused) {
  const std::vector<Vec2> surface{{0, 40}, {50, 40}};
  EXPECT_EQ(error_of([&] {
              generate_profile_mesh(profile_spec(surface, 1e-300, ElementType::quad4_1gp), 0);
            }),
            "mesh.element_size = 1e-300 m asks for about inf elements over this 50 m × 40 m "
            "profile, more than the 1e+07 the mesher builds");
  const std::string fine = error_of(
      [&] { generate_profile_mesh(profile_spec(surface, 0.01, ElementType::quad4_1gp), 0); });
  EXPECT_NE(fine.find("asks for about 2e+07 elements"), std::string::npos) << fine;
  // 0.02 m gives 5·10⁶ elements: admissible (not built here, it would take seconds).
}

TEST(BlockMesh, CellsThatMakeMoreThanTenMillionElementsAreRefused) {
  MeshSpec spec = slope_frictional_blocks(ElementType::quad4_1gp);
  spec.blocks[0].cells_u = 100000;
  spec.blocks[0].cells_v = 100001;
  EXPECT_EQ(error_of([&] { generate_block_mesh(spec, one_soil()); }),
            "mesh.blocks: the cells of the 4 block(s) make 1e+10 elements, more than the 1e+07 "
            "the mesher builds");
}

}  // namespace
}  // namespace slide
