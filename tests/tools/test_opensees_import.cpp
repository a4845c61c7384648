// OpenSees import (common/io/opensees_reader.hpp, tools/interop/opensees_import.hpp):
// small models and recorder files written here in OpenSees's formats, with values chosen
// so that every mapping shows (distinct Gauss-point values, a rigid translation, u–p
// nodes); and the one-line errors of bad or inconsistent files.
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "common/input/case_file.hpp"
#include "common/io/opensees_reader.hpp"
#include "tests/support/errors.hpp"
#include "tools/interop/opensees_import.hpp"
#include "tools/synthetic/soil.hpp"

namespace slide {
namespace {

using testing::error_of;
using ::testing::HasSubstr;

/// The running test's own folder: ctest runs the tests of this file in parallel.
std::filesystem::path scratch_folder() {
  const auto* test = ::testing::UnitTest::GetInstance()->current_test_info();
  return std::filesystem::temp_directory_path() / "slide_tests_opensees_import" /
         (std::string(test->test_suite_name()) + "." + test->name());
}

std::filesystem::path write(const std::string& name, const std::string& text) {
  const std::filesystem::path scratch = scratch_folder();
  std::filesystem::create_directories(scratch);
  const auto path = scratch / name;
  std::ofstream(path) << text;
  return path;
}

/// OpenSees's JSON print of a model: `nodes` and `elements` are the lines of the geometry
/// arrays. The properties hold a PressureIndependMultiYield material as OpenSees prints
/// it, plain text that makes the document invalid JSON: the reader must not need them.
std::string opensees_json(const std::vector<std::string>& nodes,
                          const std::vector<std::string>& elements) {
  const auto join = [](const std::vector<std::string>& lines) {
    std::string out;
    for (std::size_t i = 0; i < lines.size(); ++i)
      out += "\t\t\t" + lines[i] + (i + 1 < lines.size() ? ",\n" : "\n");
    return out;
  };
  return "{\n\t\"StructuralAnalysisModel\": {\n\t\"properties\": {\n\t\t\"ndMaterials\": [\n"
         "PressureIndependMultiYield - loadStage: 0\n\t\t]\n\t},\n\t\"geometry\": {\n"
         "\t\t\"nodes\": [\n" +
         join(nodes) + "\t\t],\n\t\t\"elements\": [\n" + join(elements) + "\t\t]\n\t}\n}\n}\n";
}

/// Two FourNodeQuads side by side over [0, 2] × [0, 1], listed out of tag order; node
/// tags 10…60 (not contiguous).
std::string two_quads(const std::string& type = "FourNodeQuad", int ndf = 2) {
  const auto node = [&](int tag, double x, double y) {
    return fmt::format(R"({{"name": {}, "ndf": {}, "crd": [{}, {}]}})", tag, ndf, x, y);
  };
  const auto element = [&](int tag, const char* nodes) {
    return fmt::format(
        R"({{"name": {}, "type": "{}", "nodes": [{}], "thickness": 1, "material": "3"}})", tag,
        type, nodes);
  };
  return opensees_json({node(60, 2, 1), node(10, 0, 0), node(20, 1, 0), node(30, 2, 0),
                        node(40, 0, 1), node(50, 1, 1)},
                       {element(2, "20, 30, 60, 50"), element(1, "10, 20, 50, 40")});
}

/// The reader needs the materials' names only.
MaterialTable soil() {
  return {slide::synthetic::soil()};
}

const std::map<std::string, std::string> tag_3_is_soil{{"3", "soil"}};

std::string read_error(const std::string& json, std::vector<std::string> ignore = {}) {
  const auto path = write("model.json", json);
  std::string message = error_of([&] { read_opensees_mesh(path, tag_3_is_soil, ignore, soil()); });
  const std::string prefix = scratch_folder().string() + "/";
  if (message.rfind(prefix, 0) == 0) message.erase(0, prefix.size());
  return message;
}

TEST(OpenSeesReader, ReadsTheGeometryOfAnInvalidDocumentInTagOrder) {
  const auto path = write("model.json", two_quads());
  const OpenSeesMesh m = read_opensees_mesh(path, tag_3_is_soil, {}, soil());
  EXPECT_EQ(m.element_class, "FourNodeQuad");
  EXPECT_EQ(m.mesh.element_type, ElementType::quad4_2x2);
  EXPECT_EQ(m.node_tags, (std::vector<std::int64_t>{10, 20, 30, 40, 50, 60}));
  EXPECT_EQ(m.element_tags, (std::vector<std::int64_t>{1, 2}));
  EXPECT_EQ(m.mesh.nodes[5], Vec2(2.0, 1.0));
  EXPECT_EQ(m.mesh.connectivity, (std::vector<Index>{0, 1, 4, 3, 1, 2, 5, 4}));
  EXPECT_EQ(m.mesh.material_id, (std::vector<std::int32_t>{0, 0}));
  ASSERT_EQ(m.mesh.node_sets.size(), 3U);
  EXPECT_EQ(m.mesh.node_sets[0].name, "left");
  EXPECT_EQ(m.mesh.node_sets[0].nodes, (std::vector<Index>{0, 3}));
  EXPECT_EQ(m.mesh.node_sets[1].nodes, (std::vector<Index>{2, 5}));
  EXPECT_EQ(m.mesh.node_sets[2].name, "base");
  EXPECT_EQ(m.mesh.node_sets[2].nodes, (std::vector<Index>{0, 1, 2}));
}

TEST(OpenSeesReader, MapsEachElementClassToItsRule) {
  EXPECT_EQ(opensees_element_type("SSPquad"), ElementType::quad4_1gp);
  EXPECT_EQ(opensees_element_type("SSPquadUP"), ElementType::quad4_1gp);
  EXPECT_EQ(opensees_element_type("Tri31"), ElementType::tri3);
  EXPECT_EQ(opensees_element_type("FourNodeQuad"), ElementType::quad4_2x2);
  EXPECT_FALSE(opensees_element_type("quad9n"));
}

TEST(OpenSeesReader, SkipsIgnoredClassesAndTheirNodes) {
  std::string json = two_quads();
  const std::string dashpot =
      R"({"name": 9, "type": "ZeroLength", "nodes": [10, 70], "material": "5"})";
  json.replace(json.find("\t\t\t{\"name\": 2,"), 0, "\t\t\t" + dashpot + ",\n");
  json.replace(json.find("\t\t\t{\"name\": 60,"), 0,
               "\t\t\t{\"name\": 70, \"ndf\": 2, \"crd\": [0, -1]},\n");
  EXPECT_EQ(read_error(json),
            "model.json: element 9 is a ZeroLength, which the import does not read (it reads "
            "FourNodeQuad, SSPquad, SSPquadUP, Tri31; list other classes in mesh.ignore_elements "
            "to skip them)");
  const auto path = write("model.json", json);
  const OpenSeesMesh m = read_opensees_mesh(path, tag_3_is_soil, {"ZeroLength"}, soil());
  EXPECT_EQ(m.mesh.node_count(), 6);  // node 70 only held the dashpot
  EXPECT_EQ(m.all_node_tags.size(), 7U);
  EXPECT_EQ(m.ignored.at("ZeroLength"), 1);
}

TEST(OpenSeesReader, RefusesBadModelsInOneLine) {
  std::string mixed = two_quads();
  mixed.replace(mixed.find("FourNodeQuad"), 12, "SSPquad");
  EXPECT_EQ(read_error(mixed),
            "model.json: element 1 is a FourNodeQuad and element 2 a SSPquad: the import reads "
            "one element class per model");
  std::string three_d = two_quads();
  three_d.replace(three_d.find("[0, 0]"), 6, "[0, 0, 0]");
  EXPECT_EQ(read_error(three_d),
            "model.json: node 10 has 3 coordinates, expected 2 (a 2D model: model BasicBuilder "
            "-ndm 2)");
  std::string missing_node = two_quads();
  missing_node.replace(missing_node.find("20, 30, 60"), 10, "20, 31, 60");
  EXPECT_EQ(read_error(missing_node),
            "model.json: element 2 uses node 31, which the model does not have");
  std::string unmapped = two_quads();
  unmapped.replace(unmapped.find("\"material\": \"3\""), 15, "\"material\": \"4\"");
  EXPECT_THAT(read_error(unmapped),
              HasSubstr("element 2 has material 4, which mesh.materials does not map"));
  std::string no_crd = two_quads();
  no_crd.replace(no_crd.find("\"crd\""), 5, "\"xyz\"");
  EXPECT_EQ(read_error(no_crd), "model.json: node 60: field \"crd\" missing");
  std::string broken = two_quads();
  broken.replace(broken.find("\"elements\": ["), 13, "\"elements\": [,");
  EXPECT_THAT(read_error(broken), HasSubstr("model.json:17: invalid JSON in \"geometry\""));
  EXPECT_EQ(read_error(two_quads().substr(0, 300)),
            "model.json:8: the \"geometry\" object does not close (truncated file?)");
  EXPECT_EQ(read_error("{\"nodes\": []}"),
            "model.json: no \"geometry\" object: not a model printed by OpenSees's print -JSON");
}

TEST(OpenSeesReader, NamesBadElementsAndNodesByTheirTags) {
  // Element 2 (the second in the mesh, index 1) with its nodes clockwise: every corner's
  // det J is −0.25, the first at node 20 (mesh node 1).
  std::string clockwise = two_quads();
  clockwise.replace(clockwise.find("20, 30, 60, 50"), 14, "20, 50, 60, 30");
  EXPECT_EQ(read_error(clockwise),
            "model.json: element 2 (nodes 20 50 60 30) is inverted or has zero area: det J = "
            "-0.25 at its node 20; expected its nodes counter-clockwise");
  // A Tri31 on three nodes in a line.
  const std::string flat =
      opensees_json({R"({"name": 7, "crd": [0, 0]})", R"({"name": 8, "crd": [1, 0]})",
                     R"({"name": 9, "crd": [2, 0]})", R"({"name": 11, "crd": [0, 1]})"},
                    {R"({"name": 4, "type": "Tri31", "nodes": [7, 8, 11], "material": "3"})",
                     R"({"name": 5, "type": "Tri31", "nodes": [7, 8, 9], "material": "3"})"});
  EXPECT_EQ(read_error(flat),
            "model.json: element 5 (nodes 7 8 9) is inverted or has zero area (signed area 0 m²): "
            "expected its nodes counter-clockwise");
  // Across the origin the bounding box's 2e-5 m takes in node 40, 1.5e-5 m inside the
  // left edge, which is more than the mesh checks' straightness of 1e-6 × 10 m.
  const std::string crooked = opensees_json(
      {R"({"name": 10, "crd": [-10, 0]})", R"({"name": 20, "crd": [0, 0]})",
       R"({"name": 30, "crd": [10, 0]})", R"({"name": 40, "crd": [-9.999985, 1]})",
       R"({"name": 50, "crd": [0, 1]})", R"({"name": 60, "crd": [10, 1]})"},
      {R"({"name": 1, "type": "FourNodeQuad", "nodes": [10, 20, 50, 40], "material": "3"})",
       R"({"name": 2, "type": "FourNodeQuad", "nodes": [20, 30, 60, 50], "material": "3"})"});
  EXPECT_EQ(read_error(crooked),
            "model.json: the left edge of the model is not straight: node 40 at (-9.999985, 1) is "
            "1.5e-05 m off the line through node 10 (expected at most 1e-05 m)");
}

// ----------------------------------------------------------------------------- recorders

std::string recorder_error(const std::string& text, double time, std::size_t columns) {
  const auto path = write("disp.out", text);
  std::string message = error_of([&] { read_recorder_row(path, time, columns, "2 per node"); });
  const std::string prefix = scratch_folder().string() + "/";
  if (message.rfind(prefix, 0) == 0) message.erase(0, prefix.size());
  return message;
}

TEST(RecorderFile, PicksTheRowAtTheTimeFirstOrLast) {
  // Gravity to t = 1, the clock reset by loadConst -time 0.0, then a dynamic step to 1 too.
  const auto path = write("disp.out", "0.5 1 2\n1 3 4\n0 5 6\n1 7 8\n\n");
  EXPECT_EQ(read_recorder_row(path, 1.0, 2, "").values, (std::vector<double>{7, 8}));
  EXPECT_EQ(read_recorder_row(path, 1.0, 2, "").line, 4U);
  EXPECT_EQ(read_recorder_row(path, 1.0, 2, "", RepeatedTime::first).values,
            (std::vector<double>{3, 4}));
  // Six significant digits of 0.5000004 still match t = 0.5.
  EXPECT_EQ(read_recorder_row(path, 0.5000004, 2, "").values, (std::vector<double>{1, 2}));
}

TEST(RecorderFile, RefusesBadRowsInOneLine) {
  EXPECT_EQ(recorder_error("0.1 1 2\n0.2 3 4\n", 0.3, 2),
            "disp.out: no row at t = 0.3 s (the rows run from t = 0.1 to 0.2 s, 2 rows)");
  EXPECT_EQ(
      recorder_error("0.1 1 2\n0.2 3 4 5\n", 0.2, 2),
      "disp.out:2: the row at t = 0.2 s has 3 values after the time, expected 2 (2 per node)");
  EXPECT_EQ(recorder_error("0.1 1 -nan\n", 0.1, 2),
            "disp.out:1: column 3 is not finite (-nan): the OpenSees analysis diverged there?");
  EXPECT_EQ(recorder_error("0.1 1 x2\n", 0.1, 2),
            "disp.out:1: column 3 reads 'x2', expected a number");
  EXPECT_EQ(recorder_error("1 2\nabc 3\n", 1.0, 1),
            "disp.out:2: the time column reads 'abc', expected a number (record with -time)");
  EXPECT_EQ(recorder_error("", 0.0, 2), "disp.out: no rows (the recorder wrote nothing)");
}

// ----------------------------------------------------------------------------- import

/// A case around the two quads, with `opensees` lines for its [opensees] table.
Case import_case(const std::string& model, const std::string& opensees) {
  write("model.json", model);
  const std::string text = R"(
[case]
name = "two-quads"
[[materials]]
name = "soil"
model = "linear-elastic"
density = 2000.0
youngs_modulus = 20.0e6
poisson_ratio = 0.25
[mesh]
generator = "opensees"
file = "model.json"
materials = { "3" = "soil" }
[fem]
failure_stage = false
[fem.geostatic.boundaries]
base = "roller"
[transfer]
main_time = 0.0
sweep_times = [0.0]
[mpm]
domain = [[-1.0, -1.0], [4.0, 4.0]]
cell_size = 0.5
end_time = 1.0
[mpm.boundaries]
base = "roller"
[metrics]
initial_length = 2.0
initial_height = 1.0
[opensees]
)" + opensees;
  return load_case(write("case.toml", text));
}

std::string nodes_row(double t, double ux, double uy) {
  std::string row = fmt::format("{}", t);
  for (int n = 0; n < 6; ++n) row += fmt::format(" {} {}", ux, uy);
  return row + "\n";
}

TEST(OpenSeesImport, MapsTheStateOfEveryField) {
  // Rows: the reference state (t = 1), then the clock reset and a rigid translation by
  // (0.1, −0.2) m moving at (3, 4) m/s.
  write("disp.out", nodes_row(1, 0.5, 0.25) + nodes_row(0, 0.5, 0.25) + nodes_row(0.2, 0.6, 0.05));
  write("vel.out", nodes_row(0, 0, 0) + nodes_row(0.2, 3, 4));
  // Stress: element 1 (first row block) then element 2, OpenSees's point order
  // (−,−), (+,−), (+,+), (−,+); σ at point q of element e = −(100 e + 10 q + component).
  std::string stress = "0.2";
  for (int e = 1; e <= 2; ++e) {
    for (int q = 0; q < 4; ++q) {
      for (int c = 0; c < 3; ++c) stress += fmt::format(" {}", -(100 * e + 10 * q + c));
    }
  }
  write("stress.out", stress + "\n");
  const Case c = import_case(two_quads(), R"(
reference_time = 1.0
displacement = "disp.out"
velocity = "vel.out"
stress = "stress.out"
)");
  const FemCheckpoint f = interop::import_opensees(c, 0.2, nullptr);
  EXPECT_EQ(f.header.time, 0.2);
  EXPECT_EQ(f.header.producer.rfind("opensees2fem (slide ", 0), 0U);
  ASSERT_EQ(f.displacement.size(), 6U);
  for (std::size_t n = 0; n < 6; ++n) {
    EXPECT_NEAR(f.displacement[n].x(), 0.1, 1e-15);
    EXPECT_NEAR(f.displacement[n].y(), -0.2, 1e-15);
    EXPECT_EQ(f.velocity[n], Vec2(3.0, 4.0));
    EXPECT_TRUE(f.coordinates[n].isApprox(f.mesh.nodes[n] + f.displacement[n]));
    EXPECT_EQ(f.acceleration[n], Vec2::Zero());
    EXPECT_EQ(f.pore_pressure[n], 0.0);
  }
  // A rigid translation strains nothing (B·u without a strain recorder).
  for (const Vec4& strain : f.strain) EXPECT_LT(strain.norm(), 1e-14);
  // Each point gets the value OpenSees recorded at the same place of the element.
  ASSERT_EQ(f.stress.size(), 8U);
  for (int e = 0; e < 2; ++e) {
    for (int p = 0; p < 4; ++p) {
      const auto gp = static_cast<std::size_t>(4 * e + p);
      const Vec2& xi = f.gauss_local_coordinates[gp];
      const int opensees_point = xi.y() < 0.0 ? (xi.x() < 0.0 ? 0 : 1) : (xi.x() > 0.0 ? 2 : 3);
      const Vec4& s = f.stress[gp];
      const double base = -(100.0 * (e + 1) + 10.0 * opensees_point);
      EXPECT_EQ(s[0], base);
      EXPECT_EQ(s[1], base - 1.0);
      EXPECT_EQ(s[3], base - 2.0);
      EXPECT_DOUBLE_EQ(s[2], 0.25 * (s[0] + s[1]));  // σzz = ν(σxx + σyy)
    }
  }
}

/// Displacement rows of the six nodes (tags 10 … 60 at (0,0), (1,0), (2,0), (0,1), (1,1),
/// (2,1)) in the linear field u = (a x, b y + g x).
std::string linear_field_row(double a, double b, double g) {
  const double xy[6][2] = {{0, 0}, {1, 0}, {2, 0}, {0, 1}, {1, 1}, {2, 1}};
  std::string row = "0";
  for (const auto& p : xy) row += fmt::format(" {} {}", a * p[0], b * p[1] + g * p[0]);
  return row + "\n";
}

TEST(OpenSeesImport, StrainsWithoutARecorderAreBTimesU) {
  // A linear displacement field strains every point alike: εxx = a, εyy = b, γxy = g.
  write("disp.out", linear_field_row(1e-3, -2e-3, 5e-4));
  write("vel.out", nodes_row(0, 0, 0));
  const std::string tri =
      opensees_json({R"({"name": 10, "crd": [0, 0]})", R"({"name": 20, "crd": [1, 0]})",
                     R"({"name": 30, "crd": [2, 0]})", R"({"name": 40, "crd": [0, 1]})",
                     R"({"name": 50, "crd": [1, 1]})", R"({"name": 60, "crd": [2, 1]})"},
                    {R"({"name": 1, "type": "Tri31", "nodes": [10, 20, 50], "material": "3"})",
                     R"({"name": 2, "type": "Tri31", "nodes": [10, 50, 40], "material": "3"})",
                     R"({"name": 3, "type": "Tri31", "nodes": [20, 30, 60], "material": "3"})",
                     R"({"name": 4, "type": "Tri31", "nodes": [20, 60, 50], "material": "3"})"});
  const std::string opensees =
      "displacement = \"disp.out\"\nvelocity = \"vel.out\"\nstress = \"stress.out\"\n";
  for (const auto& [model, points] :
       {std::pair{two_quads(), 8}, std::pair{two_quads("SSPquad"), 2}, std::pair{tri, 4}}) {
    std::string stress = "0";
    for (int k = 0; k < 3 * points; ++k) stress += " -1";
    write("stress.out", stress + "\n");
    const FemCheckpoint f = interop::import_opensees(import_case(model, opensees), 0.0, nullptr);
    ASSERT_EQ(f.strain.size(), static_cast<std::size_t>(points));
    for (const Vec4& e : f.strain) {
      EXPECT_NEAR(e[0], 1e-3, 1e-15);
      EXPECT_NEAR(e[1], -2e-3, 1e-15);
      EXPECT_EQ(e[2], 0.0);
      EXPECT_NEAR(e[3], 5e-4, 1e-15);
    }
  }
}

TEST(OpenSeesImport, ReadsThePorePressureOfUpNodes) {
  write("disp.out", nodes_row(0, 0, 0));
  write("vel.out", nodes_row(0, 0, 0));
  write("pp.out", "0 10 20 30 40 50 60\n");      // -dof 3 vel of nodes 10 … 60
  write("stress.out", "0 -1 -2 -3 -4 -5 -6\n");  // one point per SSPquadUP
  const Case c = import_case(two_quads("SSPquadUP", 3), R"(
displacement = "disp.out"
velocity = "vel.out"
pore_pressure = "pp.out"
stress = "stress.out"
)");
  const FemCheckpoint f = interop::import_opensees(c, 0.0, nullptr);
  EXPECT_EQ(f.mesh.element_type, ElementType::quad4_1gp);
  EXPECT_EQ(f.pore_pressure, (std::vector<double>{10, 20, 30, 40, 50, 60}));
  // A case without [fem.water] has no saturated element: no element pressure (the schema's
  // "saturated models only"); the nodes keep what OpenSees recorded.
  EXPECT_TRUE(f.element_pore_pressure.empty());
  ASSERT_EQ(f.stress.size(), 2U);
  EXPECT_EQ(f.stress[1], Vec4(-4, -5, 0.25 * -9, -6));
  EXPECT_EQ(f.hourglass_force.size(), 2U);
}

TEST(OpenSeesImport, TakesSigmaZzFromAMultiYieldMaterialsStress) {
  // SSPquad hands "stress" to its material; PressureIndependMultiYield answers with
  // σxx σyy σzz σxy and its stress ratio.
  write("disp.out", nodes_row(0, 0, 0));
  write("vel.out", nodes_row(0, 0, 0));
  write("stress.out", "0 -1 -2 -7 -3 0.5 -4 -5 -8 -6 0.9\n");
  const Case c = import_case(two_quads("SSPquad"), R"(
displacement = "disp.out"
velocity = "vel.out"
stress = "stress.out"
)");
  const FemCheckpoint f = interop::import_opensees(c, 0.0, nullptr);
  ASSERT_EQ(f.stress.size(), 2U);
  EXPECT_EQ(f.stress[0], Vec4(-1, -2, -7, -3));
  EXPECT_EQ(f.stress[1], Vec4(-4, -5, -8, -6));
}

TEST(OpenSeesImport, RefusesRecordersThatDoNotFitTheModel) {
  write("disp.out", "0 1 2 3 4 5 6 7 8 9 10\n");  // 5 nodes, the model has 6
  write("vel.out", nodes_row(0, 0, 0));
  write("stress.out", "0 1 2 3\n");
  const Case c = import_case(two_quads(), R"(
displacement = "disp.out"
velocity = "vel.out"
stress = "stress.out"
)");
  EXPECT_THAT(error_of([&] { interop::import_opensees(c, 0.0, nullptr); }),
              HasSubstr("disp.out:1: the row at t = 0 s has 10 values after the time, expected 12 "
                        "(-dof 1 2: 2 values for each of the model's 6 nodes, in increasing tag "
                        "order)"));
  write("disp.out", nodes_row(0, 0, 0));
  EXPECT_THAT(error_of([&] { interop::import_opensees(c, 0.0, nullptr); }),
              HasSubstr("stress.out:1: the row at t = 0 s has 3 values after the time, expected "
                        "24 (3 values (xx, yy, xy) at each of the 4 point(s) of each of the "
                        "model's 2 FourNodeQuad elements, in increasing tag order) or 40 (5 per "
                        "point: a multi-yield material's σxx σyy σzz σxy and stress ratio)"));
  EXPECT_THAT(error_of([&] { interop::import_opensees(c, 0.5, nullptr); }),
              HasSubstr("disp.out: no row at t = 0.5 s (the rows run from t = 0 to 0 s, 1 rows)"));
}

TEST(OpenSeesImport, NamesAnInvertedElementByItsTag) {
  // The case's mesh (build_mesh, then validate_mesh) meets the element before the
  // recorders: the message names OpenSees's tags, not element 1 and node 1 of the mesh.
  write("disp.out", nodes_row(0, 0, 0));
  write("vel.out", nodes_row(0, 0, 0));
  write("stress.out", "0 -1 -2 -3 -4 -5 -6\n");
  std::string clockwise = two_quads("SSPquad");
  clockwise.replace(clockwise.find("20, 30, 60, 50"), 14, "20, 50, 60, 30");
  const Case c = import_case(clockwise, R"(
displacement = "disp.out"
velocity = "vel.out"
stress = "stress.out"
)");
  EXPECT_THAT(error_of([&] { interop::import_opensees(c, 0.0, nullptr); }),
              HasSubstr("model.json: element 2 (nodes 20 50 60 30) is inverted or has zero "
                        "area: det J = -0.25 at its node 20"));
}

TEST(OpenSeesImport, NeedsAnOpenSeesCase) {
  write("disp.out", nodes_row(0, 0, 0));
  EXPECT_THAT(error_of([&] { import_case(two_quads(), "displacement = \"disp.out\"\n"); }),
              HasSubstr("opensees.velocity: missing required key"));
}

}  // namespace
}  // namespace slide
