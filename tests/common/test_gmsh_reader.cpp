// Gmsh import: the hand-written files in tests/common/data/ (the same two-quad mesh as
// 2.2 and 4.1, folded and otherwise broken meshes), and small broken files written on
// the fly. Every rejection asserts the message, which names the element, node or group.
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "common/base/error.hpp"
#include "common/input/mesh_generation.hpp"
#include "common/io/gmsh_reader.hpp"
#include "tests/support/errors.hpp"

namespace slide {
namespace {

const std::filesystem::path data_dir =
    std::filesystem::path(SLIDE_SOURCE_DIR) / "tests/common/data";

// Two materials, so that the name, not the position, picks "soil" (id 1).
MaterialTable materials() {
  Material rock;
  rock.name = "rock";
  Material soil;
  soil.name = "soil";
  return {rock, soil};
}

using testing::error_of;

/// Writes `text` to a scratch file named `name` and returns its path.
std::filesystem::path scratch_file(const std::string& name, const std::string& text) {
  const auto dir = std::filesystem::temp_directory_path() / "slide_tests_fem_gmsh";
  std::filesystem::create_directories(dir);
  const auto path = dir / name;
  std::ofstream(path) << text;
  return path;
}

/// The error of reading `text` as a .msh file, with the scratch folder cut off.
std::string read_error(const std::string& name, const std::string& text,
                       ElementType type = ElementType::quad4_1gp) {
  const auto path = scratch_file(name, text);
  std::string message = error_of([&] { read_gmsh(path, type, materials()); });
  const std::string prefix = path.parent_path().string() + "/";
  if (message.rfind(prefix, 0) == 0) message.erase(0, prefix.size());
  return message;
}

/// A 2.2 file of one unit quad (nodes 1–4, then node 5 at (2, 2) if `node_5`) with the
/// given physical names and elements; the quad is element 1 in physical surface 1 "soil".
/// Line 17 is the first element (18 with node 5).
std::string unit_quad_22(const std::string& names, const std::string& elements,
                         bool node_5 = false) {
  return "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n" + names +
         "$EndPhysicalNames\n$Nodes\n" + (node_5 ? "5" : "4") +
         "\n1 0 0 0\n2 1 0 0\n3 1 1 0\n4 0 1 0\n" + (node_5 ? "5 2 2 0\n" : "") +
         "$EndNodes\n$Elements\n" + elements + "$EndElements\n";
}

void expect_two_quads(const Mesh& mesh) {
  EXPECT_EQ(mesh.element_type, ElementType::quad4_1gp);
  // Nodes 1 2 3 7 8 9 in tag order; node 20 (used by a point element only) is dropped.
  const std::vector<Vec2> nodes{{0, 0}, {1, 0}, {2, 0}, {0, 1}, {1, 1}, {2, 1}};
  EXPECT_EQ(mesh.nodes, nodes);
  // Element 8, the whole of the clockwise surface 2 (2 8 9 3), comes back as 2 3 9 8.
  EXPECT_EQ(mesh.connectivity, (std::vector<Index>{0, 1, 4, 3, 1, 2, 5, 4}));
  EXPECT_EQ(mesh.material_id, (std::vector<std::int32_t>{1, 1}));
  // Physical lines in tag order; the top line is in no group and gives no set.
  ASSERT_EQ(mesh.node_sets.size(), 3U);
  EXPECT_EQ(mesh.node_sets[0].name, "base");
  EXPECT_EQ(mesh.node_sets[0].nodes, (std::vector<Index>{0, 1, 2}));
  EXPECT_EQ(mesh.node_sets[0].normal, Vec2(0, -1));
  EXPECT_EQ(mesh.node_sets[1].name, "left");
  EXPECT_EQ(mesh.node_sets[1].nodes, (std::vector<Index>{0, 3}));
  EXPECT_EQ(mesh.node_sets[1].normal, Vec2(-1, 0));
  EXPECT_EQ(mesh.node_sets[2].name, "toe");
  EXPECT_EQ(mesh.node_sets[2].nodes, (std::vector<Index>{2, 5}));
  EXPECT_EQ(mesh.node_sets[2].normal, Vec2(1, 0));
  EXPECT_NO_THROW(validate_mesh(mesh, "two quads", 2));
}

TEST(GmshReader, Reads22) {
  expect_two_quads(read_gmsh(data_dir / "two_quads_v22.msh", ElementType::quad4_1gp, materials()));
}

TEST(GmshReader, Reads41) {
  expect_two_quads(read_gmsh(data_dir / "two_quads_v41.msh", ElementType::quad4_1gp, materials()));
}

TEST(GmshReader, Formats22And41GiveTheSameMesh) {
  for (const auto type : {ElementType::quad4_1gp, ElementType::quad4_2x2, ElementType::tri3}) {
    const Mesh a = read_gmsh(data_dir / "two_quads_v22.msh", type, materials());
    const Mesh b = read_gmsh(data_dir / "two_quads_v41.msh", type, materials());
    EXPECT_EQ(a.element_type, type);
    EXPECT_EQ(a.nodes, b.nodes);
    EXPECT_EQ(a.connectivity, b.connectivity);
    EXPECT_EQ(a.material_id, b.material_id);
    ASSERT_EQ(a.node_sets.size(), b.node_sets.size());
    for (std::size_t s = 0; s < a.node_sets.size(); ++s) {
      EXPECT_EQ(a.node_sets[s].name, b.node_sets[s].name);
      EXPECT_EQ(a.node_sets[s].nodes, b.node_sets[s].nodes);
      EXPECT_EQ(a.node_sets[s].normal, b.node_sets[s].normal);
    }
  }
}

TEST(GmshReader, SplitsQuadsForTri3) {
  const Mesh mesh = read_gmsh(data_dir / "two_quads_v41.msh", ElementType::tri3, materials());
  // Square quads: equal diagonals, the tie goes to a–c.
  EXPECT_EQ(mesh.connectivity, (std::vector<Index>{0, 1, 4, 0, 4, 3, 1, 2, 5, 1, 5, 4}));
  EXPECT_EQ(mesh.material_id, (std::vector<std::int32_t>{1, 1, 1, 1}));
  double area = 0.0;
  for (Index e = 0; e < mesh.element_count(); ++e) {
    const double a = element_area(ElementShape::tri3, mesh.element_nodes(e, mesh.nodes));
    EXPECT_DOUBLE_EQ(a, 0.5);
    area += a;
  }
  EXPECT_DOUBLE_EQ(area, 2.0);
  EXPECT_NO_THROW(validate_mesh(mesh, "two quads tri3", 2));
}

TEST(GmshReader, SplitsAlongTheShorterDiagonal) {
  const std::string text = unit_quad_22("1\n2 1 \"soil\"\n", "1\n1 3 2 1 1 1 2 3 4\n");
  // Quad (0,0) (3,0) (1,1) (0,1): a–c is the shorter diagonal.
  std::string moved = text;
  moved.replace(moved.find("\n2 1 0 0\n"), 9, "\n2 3 0 0\n");
  auto path = scratch_file("short_diagonal.msh", moved);
  Mesh mesh = read_gmsh(path, ElementType::tri3, materials());
  EXPECT_EQ(mesh.connectivity, (std::vector<Index>{0, 1, 2, 0, 2, 3}));
  // Quad (0,0) (1,0) (3,1) (0,1): now b–d is.
  moved = text;
  moved.replace(moved.find("\n3 1 1 0\n"), 9, "\n3 3 1 0\n");
  path = scratch_file("short_diagonal.msh", moved);
  mesh = read_gmsh(path, ElementType::tri3, materials());
  EXPECT_EQ(mesh.connectivity, (std::vector<Index>{0, 1, 3, 1, 2, 3}));
}

/// A case that takes its mesh from a file of tests/common/data/ (set c.mesh.gmsh_file),
/// with an MPM grid that holds the test meshes.
Case gmsh_case() {
  Case c;
  c.file = data_dir / "case.toml";
  c.materials = materials();
  c.mesh.generator = MeshGenerator::gmsh;
  c.mpm.domain_min = Vec2(-10.0, -10.0);
  c.mpm.domain_max = Vec2(10.0, 10.0);
  return c;
}

TEST(GmshReader, RelativePathsAreRelativeToTheCaseFile) {
  Case c = gmsh_case();
  c.mesh.gmsh_file = "two_quads_v41.msh";
  c.fem.geostatic_boundaries = {{"left", BoundaryCondition::roller},
                                {"base", BoundaryCondition::roller},
                                {"toe", BoundaryCondition::roller}};
  c.fem.failure_boundaries = {{"left", BoundaryCondition::roller},
                              {"base", BoundaryCondition::friction}};
  expect_two_quads(build_mesh(c));
}

TEST(GmshReader, RejectsABoundaryWithNoPhysicalGroup) {
  Case c = gmsh_case();
  c.mesh.gmsh_file = "two_quads_v41.msh";
  c.fem.failure_boundaries = {{"left", BoundaryCondition::roller},
                              {"crest", BoundaryCondition::free}};
  EXPECT_EQ(error_of([&] { build_mesh(c); }),
            (data_dir / "two_quads_v41.msh").string() +
                ": boundary 'crest' used in fem.failure.boundaries has no physical group of that "
                "name (physical lines: base, left, toe)");
}

// The FE stage checks the grid against the body of a Gmsh mesh, which the case file
// alone cannot (two_quads_v41.msh spans (0, 0)–(2, 1) m).
TEST(GmshReader, RejectsABodyOutsideTheMpmGrid) {
  Case c = gmsh_case();
  c.mesh.gmsh_file = "two_quads_v41.msh";
  c.mpm.domain_min = Vec2(0.0, 0.0);
  c.mpm.domain_max = Vec2(1.5, 4.0);
  EXPECT_EQ(error_of([&] { build_mesh(c); }),
            (data_dir / "case.toml").string() +
                ": mpm.domain (0, 0)–(1.5, 4) m does not contain the body of " +
                (data_dir / "two_quads_v41.msh").string() +
                ", (0, 0)–(2, 1) m: its material points would start outside the MPM grid; "
                "widen mpm.domain");
  c.mpm.domain_max = Vec2(2.0, 1.0);  // touching it is inside
  expect_two_quads(build_mesh(c));
}

TEST(GmshReader, RejectsAnInvertedElement) {
  // A dart: counter-clockwise with positive area, but det J < 0 at its reflex corner.
  Case c = gmsh_case();
  c.mesh.gmsh_file = "inverted.msh";
  const std::string message = error_of([&] { build_mesh(c); });
  const std::string expected_start =
      (data_dir / "inverted.msh").string() +
      ":17: element 1 at (0.65, 0.65) is inverted or has zero area: det J = ";
  EXPECT_EQ(message.rfind(expected_start, 0), 0U) << message;
  EXPECT_NE(message.find("at its corner 2 (node 3 at (0.6, 0.6))"), std::string::npos) << message;
  // det J at the reflex corner: ((x2 − x3) × (x2 − x1)) / 4 = −0.4.
  const std::size_t det_at = expected_start.size();
  EXPECT_NEAR(std::stod(message.substr(det_at)), -0.4, 1e-12);
}

TEST(GmshReader, RejectsAZeroAreaTriangle) {
  EXPECT_EQ(read_error("flat.msh", unit_quad_22("1\n2 1 \"soil\"\n", "1\n1 2 2 1 1 1 3 5\n", true),
                       ElementType::tri3),
            "flat.msh:18: element 1 at (1, 1) is inverted or has zero area: det J = 0 at its "
            "corner 0 (node 1 at (0, 0))");
}

// A folded mesh has the area of its elements' absolute values, more than the body's:
// an element turned against the rest of its surface entity is an error.
TEST(GmshReader, RejectsAFoldedTriangleMesh) {
  const auto path = data_dir / "folded_triangles_v22.msh";
  const std::string message = error_of([&] { read_gmsh(path, ElementType::tri3, materials()); });
  // Triangle 4: nodes (1, 0), (2, 1), (1.6, 0.3); det J = 2 × signed area = −0.3.
  EXPECT_EQ(message, path.string() +
                         ":27: element 4 at (1.53333, 0.433333) is clockwise (det J = -0.3 at its "
                         "centre) but 3 of the 4 elements of surface entity 1 are "
                         "counter-clockwise: the mesh folds over itself there (Gmsh orients all "
                         "the elements of one surface alike)");
}

TEST(GmshReader, RejectsAFoldedQuadMesh) {
  const auto path = data_dir / "folded_quads_v41.msh";
  const std::string message =
      error_of([&] { read_gmsh(path, ElementType::quad4_2x2, materials()); });
  // Quad 2: the unit square (2, 0) (1, 0) (1, 1) (2, 1), det J = −¼ at its centre.
  EXPECT_EQ(message, path.string() +
                         ":41: element 2 at (1.5, 0.5) is clockwise (det J = -0.25 at its "
                         "centre) but 2 of the 3 elements of surface entity 1 are "
                         "counter-clockwise: the mesh folds over itself there (Gmsh orients all "
                         "the elements of one surface alike)");
}

TEST(GmshReader, TurnsAWhollyClockwiseSurface) {
  // Both triangles of the unit square listed clockwise, as Gmsh writes a surface whose
  // curve loop is clockwise: accepted, turned counter-clockwise, area 1.
  const Mesh mesh = read_gmsh(
      scratch_file("clockwise.msh",
                   unit_quad_22("1\n2 1 \"soil\"\n", "2\n1 2 2 1 7 1 3 2\n2 2 2 1 7 1 4 3\n")),
      ElementType::tri3, materials());
  EXPECT_EQ(mesh.connectivity, (std::vector<Index>{0, 1, 2, 0, 2, 3}));
  double area = 0.0;
  for (Index e = 0; e < mesh.element_count(); ++e) {
    area += element_area(ElementShape::tri3, mesh.element_nodes(e, mesh.nodes));
  }
  EXPECT_DOUBLE_EQ(area, 1.0);
}

TEST(GmshReader, RejectsAnEmptyPhysicalGroup) {
  // 4.1: the physical line "crest" is given to a curve that has no line elements.
  const auto path = data_dir / "empty_group_v41.msh";
  EXPECT_EQ(error_of([&] { read_gmsh(path, ElementType::quad4_1gp, materials()); }),
            path.string() +
                ":6: physical group 'crest' (dimension 1, tag 5) has no elements (a boundary "
                "named in $PhysicalNames but not meshed)");
  // 2.2: a material surface without elements.
  EXPECT_EQ(read_error("rock.msh",
                       unit_quad_22("2\n2 1 \"soil\"\n2 2 \"rock\"\n", "1\n1 3 2 1 1 1 2 3 4\n")),
            "rock.msh:7: physical group 'rock' (dimension 2, tag 2) has no elements (a material "
            "named in $PhysicalNames but not meshed)");
}

TEST(GmshReader, RejectsADanglingLine) {
  const std::string names = "2\n2 1 \"soil\"\n1 2 \"crest\"\n";
  // A line of the group "crest" from the quad's corner to node 5, off the mesh.
  EXPECT_EQ(read_error("dangling.msh",
                       unit_quad_22(names, "2\n1 3 2 1 1 1 2 3 4\n2 1 2 2 1 3 5\n", true)),
            "dangling.msh:20: line element 2 (nodes 3 and 5) of physical group 'crest' is not an "
            "edge of any surface element");
  // The same line in no physical group.
  EXPECT_EQ(read_error("loose.msh", unit_quad_22("1\n2 1 \"soil\"\n",
                                                 "2\n1 3 2 1 1 1 2 3 4\n2 1 2 0 1 3 5\n", true)),
            "loose.msh:19: line element 2 (nodes 3 and 5) in no physical group is not an edge of "
            "any surface element");
}

TEST(GmshReader, RejectsANodeNoElementUses) {
  // 4.1: the vertex of a geometry point, no element on it (Mesh.SaveAll = 0 would not
  // have saved it).
  const auto path = data_dir / "unused_node_v41.msh";
  EXPECT_EQ(error_of([&] { read_gmsh(path, ElementType::quad4_1gp, materials()); }),
            path.string() +
                ":21: node 5 at (3, 3) belongs to no element (every node of $Nodes must be a "
                "node of a surface element)");
  // 2.2: node 5 in $Nodes, in no element.
  EXPECT_EQ(
      read_error("unused.msh", unit_quad_22("1\n2 1 \"soil\"\n", "1\n1 3 2 1 1 1 2 3 4\n", true)),
      "unused.msh:14: node 5 at (2, 2) belongs to no element (every node of $Nodes must be "
      "a node of a surface element)");
  // A point element alone on it: dropped.
  const Mesh mesh = read_gmsh(
      scratch_file("point.msh",
                   unit_quad_22("1\n2 1 \"soil\"\n", "2\n1 3 2 1 1 1 2 3 4\n2 15 2 0 1 5\n", true)),
      ElementType::quad4_1gp, materials());
  EXPECT_EQ(mesh.node_count(), 4);
}

TEST(GmshReader, RejectsAnUnknownElementType) {
  const auto path = data_dir / "unknown_element_type.msh";
  EXPECT_EQ(error_of([&] { read_gmsh(path, ElementType::tri3, materials()); }),
            path.string() +
                ":19: unsupported element type 9 (6-node triangle) in element 1: only 4-node "
                "quadrangles (3), 3-node triangles (2), 2-node lines (1) and points (15) are "
                "read");
}

TEST(GmshReader, RejectsATruncatedNodesSection) {
  const auto path = data_dir / "truncated_nodes.msh";
  EXPECT_EQ(error_of([&] { read_gmsh(path, ElementType::quad4_1gp, materials()); }),
            path.string() + ":13: truncated $Nodes section: expected node 4 of 4, found $EndNodes");
}

TEST(GmshReader, RejectsMalformedFiles) {
  const std::string good_format = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n";
  EXPECT_EQ(read_error("header.msh", "$Mesh\n2.2 0 8\n"),
            "header.msh:1: not a Gmsh mesh: bad header (expected $MeshFormat, found '$Mesh')");
  EXPECT_EQ(read_error("version.msh", "\n$MeshFormat\n4.0 0 8\n$EndMeshFormat\n"),
            "version.msh:3: unsupported .msh version 4.0 (expected 4.1 or 2.2, ASCII)");
  EXPECT_EQ(read_error("binary.msh", "$MeshFormat\n4.1 1 8\n"),
            "binary.msh:2: binary .msh files are not supported (export the mesh as ASCII)");
  EXPECT_EQ(read_error("eof.msh", good_format + "$Nodes\n2\n1 0 0 0\n"),
            "eof.msh:6: truncated $Nodes section: end of file while reading node 2 of 2");
  EXPECT_EQ(read_error("skipped.msh", good_format + "$NodeData\n1\n\"u\"\n"),
            "skipped.msh:6: truncated $NodeData section: end of file while reading $EndNodeData");
  EXPECT_EQ(read_error("number.msh", good_format + "$Nodes\n1\n1 0 zero 0\n$EndNodes\n"),
            "number.msh:6: expected node 1 of 1 (a number), found 'zero'");
  EXPECT_EQ(read_error("count.msh", good_format + "$Nodes\n1\n1 0 0 0\n2 1 0 0\n$EndNodes\n"),
            "count.msh:7: expected $EndNodes (more entries than the section's count announces?), "
            "found '2'");
  EXPECT_EQ(read_error("z.msh", good_format + "$Nodes\n1\n1 0 0 2\n$EndNodes\n"),
            "z.msh:6: node 1 has z = 2 (a plane strain mesh lies in the plane z = 0)");
}

TEST(GmshReader, RejectsMeshesWithoutMeaning) {
  const std::string soil = "1\n2 1 \"soil\"\n";
  // Line 17 of unit_quad_22 is the first element.
  EXPECT_EQ(read_error("unknown_tag.msh", unit_quad_22(soil, "1\n1 3 2 1 1 1 2 3 5\n")),
            "unknown_tag.msh:17: element 1 refers to node 5, which is not in $Nodes");
  EXPECT_EQ(read_error("unknown_line_tag.msh",
                       unit_quad_22(soil, "2\n1 3 2 1 1 1 2 3 4\n2 1 2 0 1 4 6\n")),
            "unknown_line_tag.msh:18: element 2 refers to node 6, which is not in $Nodes");
  EXPECT_EQ(read_error("unknown_point_tag.msh",
                       unit_quad_22(soil, "2\n1 15 2 0 1 7\n2 3 2 1 1 1 2 3 4\n")),
            "unknown_point_tag.msh:17: element 1 refers to node 7, which is not in $Nodes");
  EXPECT_EQ(read_error("no_group.msh", unit_quad_22(soil, "1\n1 3 2 0 1 1 2 3 4\n")),
            "no_group.msh:17: surface element 1 is in no physical group (every surface needs a "
            "physical group named after its material)");
  EXPECT_EQ(read_error("clay.msh", unit_quad_22("1\n2 1 \"clay\"\n", "1\n1 3 2 1 1 1 2 3 4\n")),
            "clay.msh:6: physical surface 'clay' is not a material of the case (materials: rock, "
            "soil)");
  EXPECT_EQ(read_error("triangles.msh", unit_quad_22(soil, "1\n1 2 2 1 1 1 2 3\n"),
                       ElementType::quad4_2x2),
            "triangles.msh:17: element 1 is a triangle, which element type quad4-2x2 cannot use (a "
            "triangle mesh: 1 triangles, 0 quadrangles): use mesh.element = \"tri3\" (quadrangles "
            "are split in two), or mesh with quadrangles only (Gmsh: Mesh.RecombineAll = 1; "
            "Mesh.SubdivisionAlgorithm = 1; cases/README.md)");
  // A mixed mesh: the count of each, at the first triangle.
  EXPECT_EQ(read_error("mixed.msh", unit_quad_22(soil, "2\n1 3 2 1 1 1 2 3 4\n2 2 2 1 1 1 2 3\n"),
                       ElementType::quad4_1gp),
            "mixed.msh:18: element 2 is a triangle, which element type quad4-1gp cannot use (a "
            "mixed mesh: 1 triangles, 1 quadrangles): use mesh.element = \"tri3\" (quadrangles "
            "are split in two), or mesh with quadrangles only (Gmsh: Mesh.RecombineAll = 1; "
            "Mesh.SubdivisionAlgorithm = 1; cases/README.md)");
  EXPECT_EQ(read_error("twice.msh", unit_quad_22("2\n2 1 \"soil\"\n2 2 \"rock\"\n",
                                                 "2\n1 3 2 1 1 1 2 3 4\n1 3 2 2 1 1 2 3 4\n")),
            "twice.msh:19: surface element 1 appears twice (is it in two physical groups?); every "
            "surface element needs exactly one, naming its material");
  // An L-shaped boundary group has no single normal.
  EXPECT_EQ(
      read_error("bent.msh", unit_quad_22("2\n2 1 \"soil\"\n1 2 \"corner\"\n",
                                          "3\n1 3 2 1 1 1 2 3 4\n2 1 2 2 1 1 2\n3 1 2 2 1 2 3\n")),
      "bent.msh:19: physical group 'corner' is not straight: line element 2 is turned by 45° "
      "from the group's mean normal (0.707107, -0.707107) (a boundary needs one outward "
      "normal)");
  // A boundary line through the inside of the mesh has no outward normal either.
  EXPECT_EQ(read_error("inner.msh", unit_quad_22("2\n2 1 \"soil\"\n1 2 \"diagonal\"\n",
                                                 "2\n1 3 2 1 1 1 2 3 4\n2 1 2 2 1 1 3\n")),
            "inner.msh:19: line element 2 (nodes 1 and 3) of physical group 'diagonal' is not an "
            "edge of any surface element");
}

}  // namespace
}  // namespace slide
