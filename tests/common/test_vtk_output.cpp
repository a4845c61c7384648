// VTK output read back with VTK's own XML reader, as ParaView reads it: the mesh's cells,
// points and fields, a point cloud's fields, and the .pvd collection a run appends to and
// a restart resumes.
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
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
  write_vtk_mesh(file, points, ElementShape::quad4, connectivity,
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
  write_vtk_mesh(folder / "tri.vtu", points, ElementShape::tri3,
                 std::vector<Index>{0, 1, 2, 1, 3, 2}, {}, {});
  Grid tri;
  read(folder / "tri.vtu", tri);
  ASSERT_EQ(tri.grid->GetNumberOfCells(), 2);
  EXPECT_EQ(tri.grid->GetCellType(1), VTK_TRIANGLE);

  const std::vector<double> mass = {1.5, 2.5, 3.5, 4.5};
  const std::vector<Vec2> velocity = {{1, 2}, {3, 4}, {5, 6}, {7, 8}};
  write_vtk_points(folder / "particles.vtu", points,
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
    write_vtk_points(folder / "p.vtu", points,
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
  write_vtk_points(frame, few, {});
  const std::string former = read_text(frame);
  std::vector<Vec2> many(20000);
  std::vector<double> values(many.size());
  for (std::size_t i = 0; i < many.size(); ++i) {
    many[i] = Vec2(std::sin(0.37 * static_cast<double>(i)), std::cos(1.1 * static_cast<double>(i)));
    values[i] = std::exp(std::sin(static_cast<double>(i)));  // incompressible enough
  }
  try {
    write_vtk_points(frame, many, {vtk_field("value", values)});
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

}  // namespace
}  // namespace slide
