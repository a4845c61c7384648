// VTK output read back with VTK's own XML reader, as ParaView reads it: the mesh's cells,
// points and fields, a point cloud's fields, and the .pvd collection a run appends to and
// a restart resumes.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkFieldData.h>
#include <vtkInformation.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkStreamingDemandDrivenPipeline.h>
#include <vtkStringArray.h>
#include <vtkType.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridReader.h>

#include "common/base/error.hpp"
#include "common/io/vtk_output.hpp"
#include "tests/support/programs.hpp"
#include "tests/support/small_disk.hpp"

namespace slide {
namespace {

namespace fs = std::filesystem;

using testing::read_text;

fs::path scratch(const std::string& name) {
  return testing::fresh_folder(fs::path(SLIDE_BINARY_DIR) / "tests" / "common" / "vtk" / name);
}

struct Grid {
  vtkNew<vtkXMLUnstructuredGridReader> reader;
  vtkUnstructuredGrid* grid = nullptr;
};

void read(const fs::path& path, Grid& out) {
  out.reader->SetFileName(path.c_str());
  out.reader->Update();
  out.grid = out.reader->GetOutput();
  ASSERT_NE(out.grid, nullptr);
}

/// Every tuple of the named array equals `expected` (row by row, `components` values
/// each; a written 2-vector is read as a 3-vector with a zero third component).
void expect_array(vtkDataArray* array, const std::vector<double>& expected, int components) {
  ASSERT_NE(array, nullptr);
  const int stored = components == 2 ? 3 : components;
  ASSERT_EQ(array->GetNumberOfComponents(), stored);
  ASSERT_EQ(array->GetNumberOfTuples() * components, static_cast<vtkIdType>(expected.size()));
  for (vtkIdType i = 0; i < array->GetNumberOfTuples(); ++i) {
    for (int c = 0; c < components; ++c) {
      EXPECT_EQ(array->GetComponent(i, c), expected[static_cast<std::size_t>(i * components + c)])
          << array->GetName() << " tuple " << i << " component " << c;
    }
    if (components == 2) {
      EXPECT_EQ(array->GetComponent(i, 2), 0.0);
    }
  }
}

TEST(VtkOutput, MeshReadsBackWithItsCellsAndFields) {
  const fs::path folder = scratch("mesh");
  // Two quads and their six nodes (counter-clockwise), on current coordinates.
  const std::vector<Vec2> points = {{0, 0}, {1, 0}, {2, 0.1}, {0, 1}, {1, 1.2}, {2, 1}};
  const std::vector<Index> connectivity = {0, 1, 4, 3, 1, 2, 5, 4};
  const std::vector<Vec2> displacement = {{0, 0}, {1e-3, 0}, {2e-3, 0.1}, {0, -1}, {5, 6}, {7, 8}};
  const std::vector<Vec4> stress = {{-1, -2, -3, 0.5}, {-4, -5, -6, 0.25}};
  const std::vector<double> eps_q = {0.01, 0.25};
  const fs::path file = folder / "mesh.vtu";
  write_vtk_mesh(file, 0.0, points, ElementShape::quad4, connectivity,
                 {vtk_field("displacement", std::span<const Vec2>(displacement))},
                 {vtk_field("stress", std::span<const Vec4>(stress)),
                  vtk_field("eps_q", std::span<const double>(eps_q))});
  Grid g;
  read(file, g);
  ASSERT_EQ(g.grid->GetNumberOfPoints(), 6);
  ASSERT_EQ(g.grid->GetNumberOfCells(), 2);
  for (vtkIdType p = 0; p < 6; ++p) {
    double x[3];
    g.grid->GetPoint(p, x);
    EXPECT_EQ(x[0], points[static_cast<std::size_t>(p)].x());
    EXPECT_EQ(x[1], points[static_cast<std::size_t>(p)].y());
    EXPECT_EQ(x[2], 0.0);
  }
  for (vtkIdType e = 0; e < 2; ++e) {
    EXPECT_EQ(g.grid->GetCellType(e), VTK_QUAD);
    vtkNew<vtkIdList> ids;
    g.grid->GetCellPoints(e, ids);
    ASSERT_EQ(ids->GetNumberOfIds(), 4);
    for (vtkIdType k = 0; k < 4; ++k) {
      EXPECT_EQ(ids->GetId(k), connectivity[static_cast<std::size_t>(4 * e + k)]);
    }
  }
  std::vector<double> flat;
  for (const Vec2& d : displacement) flat.insert(flat.end(), {d.x(), d.y()});
  expect_array(g.grid->GetPointData()->GetArray("displacement"), flat, 2);
  flat.clear();
  for (const Vec4& s : stress) flat.insert(flat.end(), {s[0], s[1], s[2], s[3]});
  expect_array(g.grid->GetCellData()->GetArray("stress"), flat, 4);
  expect_array(g.grid->GetCellData()->GetArray("eps_q"), eps_q, 1);
}

TEST(VtkOutput, TrianglesAndPointCloudsReadBack) {
  const fs::path folder = scratch("points");
  const std::vector<Vec2> points = {{0, 0}, {1, 0}, {0, 1}, {1, 1}};
  write_vtk_mesh(folder / "tri.vtu", 0.0, points, ElementShape::tri3,
                 std::vector<Index>{0, 1, 2, 1, 3, 2}, {}, {});
  Grid tri;
  read(folder / "tri.vtu", tri);
  ASSERT_EQ(tri.grid->GetNumberOfCells(), 2);
  EXPECT_EQ(tri.grid->GetCellType(1), VTK_TRIANGLE);

  const std::vector<double> mass = {1.5, 2.5, 3.5, 4.5};
  const std::vector<Vec2> velocity = {{1, 2}, {3, 4}, {5, 6}, {7, 8}};
  write_vtk_points(folder / "particles.vtu", 0.0, points,
                   {vtk_field("mass", std::span<const double>(mass)),
                    vtk_field("velocity", std::span<const Vec2>(velocity))});
  Grid cloud;
  read(folder / "particles.vtu", cloud);
  ASSERT_EQ(cloud.grid->GetNumberOfPoints(), 4);
  ASSERT_EQ(cloud.grid->GetNumberOfCells(), 4);
  EXPECT_EQ(cloud.grid->GetCellType(3), VTK_VERTEX);
  expect_array(cloud.grid->GetPointData()->GetArray("mass"), mass, 1);
  expect_array(cloud.grid->GetPointData()->GetArray("velocity"), {1, 2, 3, 4, 5, 6, 7, 8}, 2);
}

TEST(VtkOutput, FieldOfTheWrongSizeIsAnErrorNamingIt) {
  const fs::path folder = scratch("wrong");
  const std::vector<Vec2> points = {{0, 0}, {1, 0}};
  const std::vector<double> short_field = {1.0};
  try {
    write_vtk_points(folder / "p.vtu", 0.0, points,
                     {vtk_field("mass", std::span<const double>(short_field))});
    FAIL() << "no error";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("mass"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(folder / "p.vtu"));
}

std::size_t count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

TEST(VtkOutput, CollectionListsItsFramesAndAResumeKeepsTheEarlierOnes) {
  const fs::path folder = scratch("pvd");
  PvdCollection run(folder / "mpm.pvd");
  for (int k = 0; k < 4; ++k)
    run.add(0.1 * k, folder / "vtk" / ("mpm_" + std::to_string(k) + ".vtu"));
  const std::string first = read_text(folder / "mpm.pvd");
  EXPECT_EQ(count(first, "<DataSet "), 4u) << first;
  EXPECT_NE(first.find("timestep=\"0.30000000000000004\""), std::string::npos) << first;
  EXPECT_NE(first.find("file=\"vtk/mpm_2.vtu\""), std::string::npos) << "relative paths: " << first;

  // A restart at t = 0.15 keeps the frames up to it and appends its own.
  PvdCollection restart(folder / "mpm.pvd");
  restart.resume(0.15);
  restart.add(0.2, folder / "vtk" / "mpm_r2.vtu");
  const std::string resumed = read_text(folder / "mpm.pvd");
  EXPECT_EQ(count(resumed, "<DataSet "), 3u) << resumed;
  EXPECT_NE(resumed.find("file=\"vtk/mpm_1.vtu\""), std::string::npos) << resumed;
  EXPECT_EQ(resumed.find("file=\"vtk/mpm_2.vtu\""), std::string::npos) << resumed;
  EXPECT_NE(resumed.find("file=\"vtk/mpm_r2.vtu\""), std::string::npos) << resumed;
}

// On a full disk VTK's XML writer returns success with the file cut short; the frame
// must fail with an error naming it, leave no temporary behind, and keep the frame of
// that name it was to replace.
TEST(VtkOutput, AFullDiskIsAnErrorAndKeepsTheFormerFrame) {
  const fs::path dir = scratch("full-disk");
  const testing::SmallDisk disk(dir / "disk", 64);
  if (!disk.mounted()) GTEST_SKIP() << "needs root to mount a 64 KiB tmpfs";
  const fs::path frame = dir / "disk" / "frame.vtu";
  const std::vector<Vec2> few{{0.0, 0.0}, {1.0, 0.0}};
  write_vtk_points(frame, 0.0, few, {});
  const std::string former = read_text(frame);
  std::vector<Vec2> many(20000);
  std::vector<double> values(many.size());
  for (std::size_t i = 0; i < many.size(); ++i) {
    many[i] = Vec2(std::sin(0.37 * static_cast<double>(i)), std::cos(1.1 * static_cast<double>(i)));
    values[i] = std::exp(std::sin(static_cast<double>(i)));  // incompressible enough
  }
  try {
    write_vtk_points(frame, 0.0, many, {vtk_field("value", values)});
    FAIL() << "a frame larger than the disk was written without an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(frame.string()), std::string::npos) << e.what();
    std::printf("full disk: %s\n", e.what());
  }
  EXPECT_EQ(read_text(frame), former);
  std::size_t files = 0;
  for (const auto& entry : fs::directory_iterator(dir / "disk")) {
    ++files;
    EXPECT_EQ(entry.path().filename(), "frame.vtu") << "left behind: " << entry.path();
  }
  EXPECT_EQ(files, 1U);
}

/// The names of the array's components, in order.
std::vector<std::string> component_names(vtkAbstractArray* array) {
  std::vector<std::string> names;
  for (int c = 0; c < array->GetNumberOfComponents(); ++c) {
    const char* name = array->GetComponentName(c);
    names.emplace_back(name != nullptr ? name : "");
  }
  return names;
}

// What ParaView is given, read back with VTK's own reader: component names on every
// multi-component array, stress-like fields also as 6-component symmetric tensors in
// ParaView's order (XX YY ZZ XY YZ XZ), integer fields as integer arrays, and the time
// and conventions as field data (the reader reports the time as the file's time step).
TEST(VtkOutput, ParaViewGetsNamedComponentsTensorsIntegerTypesAndTheTime) {
  const fs::path folder = scratch("paraview");
  const std::vector<Vec2> points = {{0, 0}, {1, 0}, {0, 1}};
  const std::vector<Vec2> velocity = {{1, 2}, {3, 4}, {5, 6}};
  const std::vector<Vec4> stress = {{-1, -2, -3, 0.5}, {-4, -5, -6, 0.25}, {7, 8, 9, -1}};
  const std::vector<Vec4> affine = {{1, 2, 3, 4}, {5, 6, 7, 8}, {9, 10, 11, 12}};
  const std::vector<std::int32_t> material = {0, 1, 2};
  const std::vector<std::int64_t> id = {7, 8'000'000'000, -1};
  const std::vector<std::uint8_t> active = {1, 0, 1};
  const fs::path file = folder / "cloud.vtu";
  write_vtk_points(file, 2.25, points,
                   {vtk_field("velocity", std::span<const Vec2>(velocity)),
                    vtk_field("stress", std::span<const Vec4>(stress)),
                    vtk_field("affine", std::span<const Vec4>(affine), VtkLayout::matrix),
                    vtk_field("material_id", std::span<const std::int32_t>(material)),
                    vtk_field("id", std::span<const std::int64_t>(id)),
                    vtk_field("active", std::span<const std::uint8_t>(active))});
  Grid g;
  read(file, g);
  vtkPointData* data = g.grid->GetPointData();
  using Names = std::vector<std::string>;
  EXPECT_EQ(component_names(data->GetArray("velocity")), (Names{"x", "y", "z"}));
  EXPECT_EQ(component_names(data->GetArray("stress")), (Names{"xx", "yy", "zz", "xy"}));
  EXPECT_EQ(component_names(data->GetArray("affine")), (Names{"xx", "xy", "yx", "yy"}));
  vtkDataArray* tensor = data->GetArray("stress_tensor");
  ASSERT_NE(tensor, nullptr);
  EXPECT_EQ(component_names(tensor), (Names{"XX", "YY", "ZZ", "XY", "YZ", "XZ"}));
  std::vector<double> six;
  for (const Vec4& s : stress) six.insert(six.end(), {s[0], s[1], s[2], s[3], 0.0, 0.0});
  expect_array(tensor, six, 6);

  ASSERT_NE(data->GetArray("material_id"), nullptr);
  EXPECT_EQ(data->GetArray("material_id")->GetDataType(), VTK_TYPE_INT32);
  EXPECT_EQ(data->GetArray("id")->GetDataType(), VTK_TYPE_INT64);
  EXPECT_EQ(data->GetArray("active")->GetDataType(), VTK_TYPE_UINT8);
  EXPECT_EQ(data->GetArray("stress")->GetDataType(), VTK_DOUBLE);
  expect_array(data->GetArray("id"), {7, 8e9, -1}, 1);
  expect_array(data->GetArray("active"), {1, 0, 1}, 1);

  vtkFieldData* field = g.grid->GetFieldData();
  ASSERT_NE(field->GetArray("TimeValue"), nullptr);
  EXPECT_EQ(field->GetArray("TimeValue")->GetTuple1(0), 2.25);
  auto* conventions = vtkStringArray::SafeDownCast(field->GetAbstractArray("conventions"));
  ASSERT_NE(conventions, nullptr);
  EXPECT_NE(conventions->GetValue(0).find("tension positive"), std::string::npos);
  EXPECT_EQ(conventions->GetValue(0), vtk_conventions);
  // The time as ParaView sees a lone .vtu: the reader's time step.
  vtkInformation* info = g.reader->GetOutputInformation(0);
  ASSERT_TRUE(info->Has(vtkStreamingDemandDrivenPipeline::TIME_STEPS()));
  ASSERT_EQ(info->Length(vtkStreamingDemandDrivenPipeline::TIME_STEPS()), 1);
  EXPECT_EQ(info->Get(vtkStreamingDemandDrivenPipeline::TIME_STEPS())[0], 2.25);
}

// Mesh cells get the same treatment as points: an integer material id per cell, the
// element stress as a tensor.
TEST(VtkOutput, MeshCellFieldsAreTypedAndNamedToo) {
  const fs::path folder = scratch("mesh-types");
  const std::vector<Vec2> points = {{0, 0}, {1, 0}, {0, 1}, {1, 1}};
  const std::vector<Vec4> stress = {{-1, -2, -3, 0.5}, {-4, -5, -6, 0.25}};
  const std::vector<std::int32_t> material = {3, 4};
  const std::vector<std::uint8_t> yielded = {0, 1};
  write_vtk_mesh(folder / "tri.vtu", 0.5, points, ElementShape::tri3,
                 std::vector<Index>{0, 1, 2, 1, 3, 2}, {},
                 {vtk_field("stress", std::span<const Vec4>(stress)),
                  vtk_field("material_id", std::span<const std::int32_t>(material)),
                  vtk_field("yielded", std::span<const std::uint8_t>(yielded))});
  Grid g;
  read(folder / "tri.vtu", g);
  vtkCellData* cells = g.grid->GetCellData();
  EXPECT_EQ(cells->GetArray("material_id")->GetDataType(), VTK_TYPE_INT32);
  EXPECT_EQ(cells->GetArray("yielded")->GetDataType(), VTK_TYPE_UINT8);
  expect_array(cells->GetArray("material_id"), {3, 4}, 1);
  ASSERT_NE(cells->GetArray("stress_tensor"), nullptr);
  EXPECT_EQ(cells->GetArray("stress_tensor")->GetNumberOfComponents(), 6);
  EXPECT_EQ(g.grid->GetFieldData()->GetArray("TimeValue")->GetTuple1(0), 0.5);
}

}  // namespace
}  // namespace slide
