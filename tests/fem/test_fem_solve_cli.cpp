// fem-solve end to end: restart bit for bit, the files of docs/contract.md (checkpoint
// times, VTK frames read back with VTK), the zone-exit checkpoint, the instability
// guard, the updated-Lagrangian stop, bad input, and a cut column-short regression
// against stored reference numbers.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <hdf5.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkFieldData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkSmartPointer.h>
#include <vtkType.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridReader.h>

#include "common/input/case_file.hpp"
#include "common/io/checkpoint.hpp"
#include "tests/support/column_case.hpp"
#include "tests/support/programs.hpp"
#include "tests/support/pvd.hpp"
#include "tests/support/small_disk.hpp"
#include "tools/synthetic/soil.hpp"

namespace slide::fem {
namespace {

namespace fs = std::filesystem;
using testing::ColumnCase;
using testing::ProgramRun;
using testing::read_text;
using testing::write_file;

const fs::path source_dir = SLIDE_SOURCE_DIR;

/// A clean scratch folder for one test.
fs::path scratch(const std::string& name) {
  return testing::fresh_folder(fs::path(SLIDE_BINARY_DIR) / "tests" / "fem" / "cli" / name);
}

/// Runs fem-solve with `arguments`, capturing stdout and stderr in `dir`.
ProgramRun fem_solve(const std::string& arguments, const fs::path& dir) {
  return testing::run_program(std::string(FEM_SOLVE) + " " + arguments, dir);
}

fs::path write_case(const fs::path& dir, const std::string& text) {
  const fs::path file = dir / "case.toml";
  write_file(file, text);
  return file;
}

/// Every file of a folder with its bytes.
std::map<std::string, std::string> snapshot(const fs::path& dir) {
  std::map<std::string, std::string> files;
  for (const auto& entry : fs::recursive_directory_iterator(dir)) {
    if (entry.is_regular_file()) files[entry.path().string()] = read_text(entry.path());
  }
  return files;
}

template <typename T>
void expect_same(const std::vector<T>& a, const std::vector<T>& b, const char* name) {
  ASSERT_EQ(a.size(), b.size()) << name;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (!(a[i] == b[i])) {
      ADD_FAILURE() << name << " differs at " << i;
      return;
    }
  }
}

/// Every dataset and attribute of two fem checkpoints, bit for bit.
void expect_identical(const fs::path& first, const fs::path& second) {
  const FemCheckpoint a = read_fem_checkpoint(first), b = read_fem_checkpoint(second);
  EXPECT_EQ(a.header.time, b.header.time);
  EXPECT_EQ(a.header.step, b.header.step);
  EXPECT_EQ(a.header.pe0, b.header.pe0);
  EXPECT_EQ(a.header.case_name, b.header.case_name);
  expect_same(a.mesh.nodes, b.mesh.nodes, "reference_coordinates");
  expect_same(a.mesh.connectivity, b.mesh.connectivity, "connectivity");
  expect_same(a.mesh.material_id, b.mesh.material_id, "material_id");
  expect_same(a.boundary_conditions, b.boundary_conditions, "boundary");
  expect_same(a.coordinates, b.coordinates, "coordinates");
  expect_same(a.displacement, b.displacement, "displacement");
  expect_same(a.velocity, b.velocity, "velocity");
  expect_same(a.acceleration, b.acceleration, "acceleration");
  expect_same(a.pore_pressure, b.pore_pressure, "pore_pressure");
  expect_same(a.static_pore_pressure, b.static_pore_pressure, "static_pore_pressure");
  expect_same(a.initial_vertical_effective_stress, b.initial_vertical_effective_stress,
              "initial_vertical_effective_stress");
  expect_same(a.jacobian_ratio, b.jacobian_ratio, "jacobian_ratio");
  expect_same(a.volume_reference, b.volume_reference, "volume_reference");
  expect_same(a.volume, b.volume, "volume");
  expect_same(a.hourglass_force, b.hourglass_force, "hourglass_force");
  expect_same(a.gauss_element, b.gauss_element, "gauss element");
  expect_same(a.gauss_local_coordinates, b.gauss_local_coordinates, "gauss local_coordinates");
  expect_same(a.gauss_coordinates, b.gauss_coordinates, "gauss coordinates");
  expect_same(a.gauss_weight, b.gauss_weight, "gauss weight");
  expect_same(a.stress, b.stress, "stress");
  expect_same(a.strain, b.strain, "strain");
  expect_same(a.eps_q, b.eps_q, "eps_q");
  ASSERT_EQ(a.material_state.size(), b.material_state.size());
  for (std::size_t i = 0; i < a.material_state.size(); ++i) {
    ASSERT_EQ(a.material_state[i].plastic_shear_strain, b.material_state[i].plastic_shear_strain)
        << i;
    ASSERT_EQ(a.material_state[i].plastic_volumetric_strain,
              b.material_state[i].plastic_volumetric_strain)
        << i;
    ASSERT_EQ(a.material_state[i].peak_strength, b.material_state[i].peak_strength) << i;
  }
  ASSERT_EQ(a.surface_stress.per_point, b.surface_stress.per_point);
  expect_same(a.surface_stress.values, b.surface_stress.values, "state/surface_stress");
  EXPECT_EQ(a.solver, b.solver);
}

/// A non-zero exit and exactly one error line, the last on stderr (warnings may come
/// before it), containing `fragment`.
void expect_one_line_error(const ProgramRun& run, const std::string& fragment) {
  EXPECT_NE(run.status, 0);
  const auto start = run.err.find("fem-solve: error: ");
  ASSERT_NE(start, std::string::npos) << run.err;
  const std::string error = run.err.substr(start);
  EXPECT_EQ(std::count(error.begin(), error.end(), '\n'), 1) << run.err;
  EXPECT_EQ(error.back(), '\n');
  EXPECT_NE(error.find(fragment), std::string::npos) << run.err;
}

/// `base` (fem-solve's case and options up to -o) run whole into dir/one, and into dir/two
/// to 0.2 s and then restarted from its fem_t0.200.h5 to the end.
void run_and_restart(const std::string& base, const fs::path& dir) {
  ASSERT_EQ(fem_solve(base + (dir / "one").string(), dir).status, 0);
  ASSERT_EQ(fem_solve(base + (dir / "two").string() + " --until 0.2", dir).status, 0);
  ASSERT_EQ(fem_solve(base + (dir / "two").string() + " --restart " +
                          (dir / "two" / "fem_t0.200.h5").string(),
                      dir)
                .status,
            0);
}

TEST(FemSolveCli, RestartContinuesBitForBit) {
  struct Variant {
    std::string element, kinematics;
    std::string model = "mohr-coulomb";
    std::string damping;  // more [fem] lines
  };
  // The multi-yield soil carries its frozen strengths and 20 surfaces per Gauss point
  // through the checkpoint; stiffness damping reads the velocities of the checkpoint.
  const std::string mohr_coulomb = "mohr-coulomb";
  const std::string multi_yield = "pressure-independent-multi-yield";
  const std::string damped = "\n[fem.damping]\nrayleigh_stiffness = 0.005\n";
  for (const Variant& v : {Variant{"quad4-1gp", "small-strain", mohr_coulomb, ""},
                           Variant{"quad4-2x2", "small-strain", mohr_coulomb, ""},
                           Variant{"tri3", "updated-lagrangian", mohr_coulomb, ""},
                           Variant{"quad4-1gp", "small-strain", multi_yield, damped},
                           Variant{"quad4-2x2", "updated-lagrangian", multi_yield, ""}}) {
    SCOPED_TRACE(v.element + " " + v.kinematics + " " + v.model +
                 (v.damping.empty() ? "" : " damped"));
    const fs::path dir = scratch("restart-" + v.element + "-" + v.kinematics + "-" + v.model +
                                 (v.damping.empty() ? "" : "-damped"));
    ColumnCase column;
    column.element = v.element;
    column.kinematics = v.kinematics;
    column.model = v.model;
    column.extra_fem = v.damping;
    const fs::path case_file = write_case(dir, column.text());
    const std::string base = case_file.string() + " --quiet -o ";
    run_and_restart(base, dir);
    if (::testing::Test::HasFatalFailure()) return;
    expect_identical(dir / "one" / "fem_t0.400.h5", dir / "two" / "fem_t0.400.h5");
    EXPECT_EQ(read_text(dir / "one" / "fem_history.csv"),
              read_text(dir / "two" / "fem_history.csv"));
    // From the geostatic checkpoint the switch to the plastic models happens again.
    ASSERT_EQ(fem_solve(base + (dir / "three").string() + " --restart " +
                            (dir / "one" / "fem_t0.000.h5").string(),
                        dir)
                  .status,
              0);
    expect_identical(dir / "one" / "fem_t0.400.h5", dir / "three" / "fem_t0.400.h5");
  }
}

/// The rows of a fem_history.csv by time in tenths of a second (defined below).
std::map<int, std::vector<double>> history_rows(const fs::path& file);

// A saturated column (fem/pore_fluid.hpp) whose right face is released: the pore
// pressure moves with the collapse, and a restart continues it bit for bit, the
// pore-pressure ratio's references (p_static, σ′v0) carried through the checkpoint.
TEST(FemSolveCli, SaturatedRestartContinuesBitForBit) {
  for (const auto& [element, kinematics] :
       {std::pair<std::string, std::string>{"quad4-1gp", "small-strain"},
        std::pair<std::string, std::string>{"tri3", "updated-lagrangian"}}) {
    SCOPED_TRACE(element + " " + kinematics);
    const fs::path dir = scratch("restart-saturated-" + element);
    ColumnCase column;
    column.element = element;
    column.kinematics = kinematics;
    column.extra_material = "porosity = 0.4\nconductivity = 1e-4\n";
    column.extra_fem =
        "\n[fem.water]\nlevel = 5.0\nbulk_modulus = 0.5e9\n\n[[fem.recorders]]\nname = "
        "\"water\"\npoints = [[9.0, 1.0]]\nevery = 0.01\n\n[[fem.recorders]]\nname = "
        "\"water-elements\"\nelements = [[5.5, 0.5]]\nevery = 0.01\n";
    const fs::path case_file = write_case(dir, column.text());
    const std::string base = case_file.string() + " --quiet -o ";
    run_and_restart(base, dir);
    if (::testing::Test::HasFatalFailure()) return;
    expect_identical(dir / "one" / "fem_t0.400.h5", dir / "two" / "fem_t0.400.h5");
    // Recorders add p and Δp per node and p and r_u per element, and continue through the
    // restart as the run does.
    std::string columns;
    for (const char* name : {"water.csv", "water-elements.csv"}) {
      const std::string recorded = read_text(dir / "one" / "recorders" / name);
      EXPECT_EQ(recorded, read_text(dir / "two" / "recorders" / name)) << name;
      columns += recorded.substr(0, recorded.find('\n')) + ",";
    }
    for (const char* suffix : {"_p,", "_dp,", "_ru,"}) {
      EXPECT_NE(columns.find(suffix), std::string::npos) << suffix << " in " << columns;
    }
    // The history gains the largest r_u and the area with r_u ≥ 0.7: 0 at rest (t = 0),
    // and it continues through the restart too.
    const std::string history = read_text(dir / "one" / "fem_history.csv");
    EXPECT_EQ(history, read_text(dir / "two" / "fem_history.csv"));
    const std::string first = history.substr(0, history.find('\n'));
    EXPECT_TRUE(first.ends_with(",pore_pressure_ratio_max,high_pore_pressure_area")) << first;
    const auto rows = history_rows(dir / "one" / "fem_history.csv");
    ASSERT_FALSE(rows.empty());
    EXPECT_EQ(rows.begin()->second.at(12), 0.0);  // t = 0: no excess pore pressure
    EXPECT_EQ(rows.begin()->second.at(13), 0.0);
    EXPECT_GT(rows.rbegin()->second.at(12), 0.0);
    // The collapse did move the water: p is no longer the hydrostatic field.
    const FemCheckpoint end = read_fem_checkpoint(dir / "one" / "fem_t0.400.h5");
    double largest_excess = 0.0;
    for (std::size_t n = 0; n < end.pore_pressure.size(); ++n) {
      largest_excess =
          std::max(largest_excess, std::abs(end.pore_pressure[n] - end.static_pore_pressure[n]));
    }
    EXPECT_GT(largest_excess, 1e3);
  }
}

TEST(FemSolveCli, ADampingThatWouldTakeForeverIsAOneLineError) {
  // β_K = 1e300 s lowers the stable step to nothing: refused instead of hanging.
  const fs::path dir = scratch("huge-damping");
  ColumnCase column;
  column.extra_fem = "\n[fem.damping]\nrayleigh_stiffness = 1e300\n";
  const fs::path case_file = write_case(dir, column.text());
  const ProgramRun run =
      fem_solve(case_file.string() + " -o " + (dir / "out").string() + " --quiet", dir);
  expect_one_line_error(run, "fem.damping.rayleigh_stiffness = 1e+300 s lowers the stable step");
}

TEST(FemSolveCli, WritesTheContractFiles) {
  const fs::path dir = scratch("files");
  const fs::path case_file = write_case(dir, ColumnCase{}.text());
  const ProgramRun run =
      fem_solve(case_file.string() + " -o " + (dir / "out").string() + " --quiet", dir);
  ASSERT_EQ(run.status, 0) << run.err;
  // --quiet: only the summary line.
  EXPECT_EQ(run.out.rfind("summary: steps=", 0), 0U) << run.out;
  EXPECT_NE(run.out.find(" elements=80 wall_s="), std::string::npos) << run.out;
  EXPECT_NE(run.out.find(" element_steps_per_s="), std::string::npos) << run.out;
  EXPECT_EQ(std::count(run.out.begin(), run.out.end(), '\n'), 1);
  for (const char* name : {"fem_t0.000.h5", "fem_t0.200.h5", "fem_t0.400.h5", "fem_history.csv",
                           "fem.pvd", "fem_gauss_points.pvd", "fem_summary.txt"}) {
    EXPECT_TRUE(fs::exists(dir / "out" / name)) << name;
  }
  std::istringstream history(read_text(dir / "out" / "fem_history.csv"));
  std::string line;
  std::getline(history, line);
  EXPECT_EQ(line,
            "time,kinetic_energy,pe0,ke_over_pe0,jacobian_ratio_min,jacobian_ratio_avg,eps_q_avg,"
            "eps_q_max,n_elements_yielding,area_ratio,scaled_jacobian_min,scaled_jacobian_avg");
  std::vector<double> times;
  while (std::getline(history, line)) times.push_back(std::stod(line));
  ASSERT_EQ(times.size(), 5U);
  for (std::size_t i = 0; i < times.size(); ++i) {
    EXPECT_NEAR(times[i], 0.1 * static_cast<double>(i), 1e-12);
  }
  // t = 0 holds the geostatic state; later checkpoints the failure stage.
  const FemCheckpoint first = read_fem_checkpoint(dir / "out" / "fem_t0.000.h5");
  EXPECT_EQ(std::get<std::string>(first.solver.at("stage")), "geostatic");
  EXPECT_EQ(first.header.time, 0.0);
  const FemCheckpoint last = read_fem_checkpoint(dir / "out" / "fem_t0.400.h5");
  EXPECT_EQ(std::get<std::string>(last.solver.at("stage")), "failure");
  EXPECT_EQ(last.header.pe0, first.header.pe0);
  EXPECT_EQ(fs::exists(dir / "out" / "vtk" / fmt::format("fem_{:06d}.vtu", last.header.step)),
            true);
}

/// A .vtu file read back with VTK's own reader.
vtkSmartPointer<vtkUnstructuredGrid> read_vtu(const fs::path& path) {
  vtkNew<vtkXMLUnstructuredGridReader> reader;
  reader->SetFileName(path.c_str());
  reader->Update();
  return reader->GetOutput();
}

using slide::testing::pvd_entries;

TEST(FemSolveCli, VtkFramesHoldTheFieldsOfTheCheckpoints) {
  // The column (80 quads, 99 nodes) to 0.4 s with outputs every 0.1 s: fem.pvd lists the
  // five frames, each read back by VTK holds the point and cell arrays of fem/README.md
  // with one tuple per node or element, and the frames at the checkpoint times carry
  // the checkpoint's current coordinates, displacement and |J_t|/|J_0|.
  const fs::path dir = scratch("vtk");
  const fs::path case_file = write_case(dir, ColumnCase{}.text());
  const ProgramRun run =
      fem_solve(case_file.string() + " -o " + (dir / "out").string() + " -q", dir);
  ASSERT_EQ(run.status, 0) << run.err;
  const auto frames = pvd_entries(dir / "out" / "fem.pvd");
  ASSERT_EQ(frames.size(), 5U);
  std::map<double, fs::path> frame_at;
  for (std::size_t i = 0; i < frames.size(); ++i) {
    EXPECT_NEAR(frames[i].first, 0.1 * static_cast<double>(i), 1e-12);
    EXPECT_TRUE(fs::exists(dir / "out" / frames[i].second)) << frames[i].second;
    frame_at[frames[i].first] = dir / "out" / frames[i].second;
  }
  std::size_t mesh_files = 0;
  for (const auto& entry : fs::directory_iterator(dir / "out" / "vtk")) {
    mesh_files += entry.path().filename().string().rfind("fem_0", 0) == 0 ? 1 : 0;
  }
  EXPECT_EQ(mesh_files, frames.size()) << "a frame the collection does not list";
  EXPECT_EQ(pvd_entries(dir / "out" / "fem_gauss_points.pvd").size(), frames.size());

  for (const double time : {0.2, 0.4}) {
    SCOPED_TRACE(time);
    const FemCheckpoint c = read_fem_checkpoint(dir / "out" / fmt::format("fem_t{:.3f}.h5", time));
    const auto found = std::find_if(frame_at.begin(), frame_at.end(), [&](const auto& f) {
      return std::abs(f.first - c.header.time) < 1e-9;
    });
    ASSERT_NE(found, frame_at.end());
    EXPECT_EQ(found->second.filename().string(), fmt::format("fem_{:06d}.vtu", c.header.step));
    const auto grid = read_vtu(found->second);
    ASSERT_NE(grid, nullptr);
    const auto nodes = static_cast<vtkIdType>(c.coordinates.size());
    const auto elements = static_cast<vtkIdType>(c.jacobian_ratio.size());
    ASSERT_EQ(grid->GetNumberOfPoints(), nodes);
    ASSERT_EQ(grid->GetNumberOfCells(), elements);
    ASSERT_EQ(nodes, 99);
    ASSERT_EQ(elements, 80);
    struct Expected {
      const char* name;
      bool point;
      int components;
    };
    for (const Expected& e : {Expected{"displacement", true, 3}, Expected{"velocity", true, 3},
                              Expected{"stress", false, 4}, Expected{"strain", false, 4},
                              Expected{"eps_q", false, 1}, Expected{"jacobian_ratio", false, 1}}) {
      vtkDataArray* array =
          e.point ? grid->GetPointData()->GetArray(e.name) : grid->GetCellData()->GetArray(e.name);
      ASSERT_NE(array, nullptr) << e.name;
      EXPECT_EQ(array->GetNumberOfTuples(), e.point ? nodes : elements) << e.name;
      EXPECT_EQ(array->GetNumberOfComponents(), e.components) << e.name;
    }
    // ParaView's view of the frame: its time, typed integers, the stress as a tensor.
    ASSERT_NE(grid->GetFieldData()->GetArray("TimeValue"), nullptr);
    EXPECT_EQ(grid->GetFieldData()->GetArray("TimeValue")->GetTuple1(0), c.header.time);
    ASSERT_NE(grid->GetCellData()->GetArray("material_id"), nullptr);
    EXPECT_EQ(grid->GetCellData()->GetArray("material_id")->GetDataType(), VTK_TYPE_INT32);
    EXPECT_EQ(grid->GetCellData()->GetArray("yielded")->GetDataType(), VTK_TYPE_UINT8);
    ASSERT_NE(grid->GetCellData()->GetArray("stress_tensor"), nullptr);
    EXPECT_EQ(grid->GetCellData()->GetArray("stress_tensor")->GetNumberOfComponents(), 6);
    vtkDataArray* ratio = grid->GetCellData()->GetArray("jacobian_ratio");
    vtkDataArray* displacement = grid->GetPointData()->GetArray("displacement");
    for (vtkIdType e = 0; e < elements; ++e) {
      EXPECT_EQ(ratio->GetTuple1(e), c.jacobian_ratio[static_cast<std::size_t>(e)]) << e;
    }
    for (vtkIdType n = 0; n < nodes; ++n) {
      const auto i = static_cast<std::size_t>(n);
      double x[3];
      grid->GetPoint(n, x);
      EXPECT_EQ(Vec2(x[0], x[1]), c.coordinates[i]) << n;
      EXPECT_EQ(Vec2(displacement->GetComponent(n, 0), displacement->GetComponent(n, 1)),
                c.displacement[i])
          << n;
    }
  }
}

// geostatic-4x4 stops after stage 1, so its only checkpoint is the geostatic state as
// fem-solve writes it. On the roller column that state is the closed form
//   σyy = −ρ g (H − y),  σxx = σzz = K0 σyy,  K0 = ν/(1 − ν),  σxy = 0,
// and the one-point quads carry it exactly at their centres (tests/fem/test_geostatic.cpp
// explains why), so every Gauss point read back from the file must match it to
// round-off: 1e-12 ρ g H for the normal stresses, 1e-9 ρ g H for the shear. ρ and ν
// come from the case file, H from the checkpoint's mesh; a wrong gravity, boundary
// table, K0 or dataset layout in the file shows up here.
TEST(FemSolveCli, GeostaticOnlyCaseCheckpointsTheClosedFormColumn) {
  const fs::path dir = scratch("geostatic-only");
  const fs::path case_file = source_dir / "cases" / "geostatic-4x4" / "case.toml";
  const ProgramRun run =
      fem_solve(case_file.string() + " -o " + (dir / "out").string() + " --quiet --no-vtk", dir);
  ASSERT_EQ(run.status, 0) << run.err;
  EXPECT_EQ(run.out.rfind("summary: steps=0 elements=256 ", 0), 0U) << run.out;
  std::size_t checkpoints = 0;
  for (const auto& entry : fs::directory_iterator(dir / "out")) {
    checkpoints += entry.path().extension() == ".h5" ? 1 : 0;
  }
  EXPECT_EQ(checkpoints, 1U);

  const FemCheckpoint geostatic = read_fem_checkpoint(dir / "out" / "fem_t0.000.h5");
  EXPECT_EQ(std::get<std::string>(geostatic.solver.at("stage")), "geostatic");
  EXPECT_EQ(geostatic.header.time, 0.0);
  const Material soil = load_case(case_file).materials.at(0);
  double height = 0.0;
  for (const Vec2& x : geostatic.mesh.nodes) height = std::max(height, x.y());
  ASSERT_DOUBLE_EQ(height, 4.0);
  const double rho_g = soil.density * gravity_acceleration;
  const double k0 = soil.poisson_ratio / (1.0 - soil.poisson_ratio);
  ASSERT_EQ(geostatic.stress.size(), 256U);  // one Gauss point per element
  ASSERT_EQ(geostatic.gauss_coordinates.size(), geostatic.stress.size());
  double normal_error = 0.0, shear = 0.0;
  for (std::size_t gp = 0; gp < geostatic.stress.size(); ++gp) {
    const Vec4& stress = geostatic.stress[gp];
    const double syy = -rho_g * (height - geostatic.gauss_coordinates[gp].y());
    normal_error = std::max({normal_error, std::abs(stress[0] - k0 * syy),
                             std::abs(stress[1] - syy), std::abs(stress[2] - k0 * syy)});
    shear = std::max(shear, std::abs(stress[3]));
  }
  EXPECT_LT(normal_error, 1e-12 * rho_g * height);
  EXPECT_LT(shear, 1e-9 * rho_g * height);
  // t = 0 is the undeformed column at rest: the geostatic stage keeps no displacement.
  for (const Vec2& u : geostatic.displacement) ASSERT_EQ(u, Vec2::Zero());
  for (const Vec2& v : geostatic.velocity) ASSERT_EQ(v, Vec2::Zero());
}

/// The rows of a fem_history.csv by time in tenths of a second.
std::map<int, std::vector<double>> history_rows(const fs::path& file) {
  std::istringstream history(read_text(file));
  std::string line;
  std::getline(history, line);
  std::map<int, std::vector<double>> rows;
  while (std::getline(history, line)) {
    std::vector<double> values;
    std::stringstream fields(line);
    for (std::string field; std::getline(fields, field, ',');) values.push_back(std::stod(field));
    rows[static_cast<int>(std::lround(10.0 * values[0]))] = values;
  }
  return rows;
}

/// column-short's case file with the FE model and the damping of the first version:
/// Mohr–Coulomb, no damping (written next to `dir`).
fs::path column_short_with_mohr_coulomb(const fs::path& dir) {
  std::string text = read_text(source_dir / "cases" / "column-short" / "case.toml");
  for (const auto& [from, to] :
       {std::pair<std::string, std::string>{"fem_model = \"pressure-independent-multi-yield\"",
                                            "fem_model = \"mohr-coulomb\""},
        {"rayleigh_stiffness = 0.005626", "rayleigh_stiffness = 0.0"}}) {
    const auto at = text.find(from);
    if (at == std::string::npos) throw std::runtime_error("column-short case.toml: no " + from);
    text.replace(at, from.size(), to);
  }
  fs::create_directories(dir);
  const fs::path file = dir / "case.toml";
  std::ofstream(file) << text;
  return file;
}

TEST(FemSolveCli, ColumnShortWithItsCaseModelsRegression) {
  // The case defaults (multi-yield soil in FE, β_K = 5.6e-3 s) to 4.1 s, against the
  // numbers of the reference run (fem/README.md). Tolerances as in the Mohr–Coulomb
  // regression below; the inversion times are output steps, exact.
  const fs::path dir = scratch("column-short-case-models");
  const ProgramRun run =
      fem_solve((source_dir / "cases" / "column-short" / "case.toml").string() + " -o " +
                    (dir / "out").string() + " --quiet --no-vtk --until 4.1",
                dir);
  ASSERT_EQ(run.status, 0) << run.err;
  auto rows = history_rows(dir / "out" / "fem_history.csv");
  ASSERT_EQ(rows.size(), 42U);
  EXPECT_NEAR(rows[10][3] / 0.01047560821, 1.0, 0.02);  // KE/PE0 at 1 s
  EXPECT_NEAR(rows[20][3] / 0.0315189536, 1.0, 0.02);   // KE/PE0 at 2 s
  EXPECT_NEAR(rows[20][4], 0.7727609017, 0.01);         // (|J_t|/|J_0|)_min at 2 s
  EXPECT_NEAR(rows[20][7] / 0.8953915966, 1.0, 0.02);   // εq,max at 2 s
  EXPECT_NEAR(rows[20][9], 0.98996, 0.005);             // area ratio at 2 s
  EXPECT_GT(rows[39][4], 0.0);                          // not yet inverted at 3.9 s
  EXPECT_LT(rows[40][4], 0.0);                          // inverted at 4.0 s
  const std::string summary = read_text(dir / "out" / "fem_summary.txt");
  EXPECT_NE(summary.find("last_time_in_zone = 2.200\n"), std::string::npos) << summary;
  EXPECT_NE(summary.find("first_time_inverted = 4.000\n"), std::string::npos) << summary;
  EXPECT_NE(summary.find("first_time_jacobian_ratio_negative = 4.000\n"), std::string::npos);
}

TEST(FemSolveCli, ColumnShortRegression) {
  // The first two seconds of the column-short failure stage with Mohr–Coulomb in FE and
  // no damping (the first version's case), against the numbers of the reference run
  // (small strain, quad4-1gp; fem/README.md). Tolerances: 2 % on KE/PE0 and εq,max, 0.01
  // on (|J_t|/|J_0|)_min: round-off differences between compilers grow slowly in this
  // smooth phase, a change of the physics shifts these numbers by far more.
  const fs::path dir = scratch("column-short");
  const ProgramRun run = fem_solve(column_short_with_mohr_coulomb(dir).string() + " -o " +
                                       (dir / "out").string() + " --quiet --no-vtk --until 2",
                                   dir);
  ASSERT_EQ(run.status, 0) << run.err;
  auto rows = history_rows(dir / "out" / "fem_history.csv");
  ASSERT_EQ(rows.size(), 21U);
  EXPECT_NEAR(rows[10][3] / 0.03715871103, 1.0, 0.02);  // KE/PE0 at 1 s
  EXPECT_NEAR(rows[20][3] / 0.1305172089, 1.0, 0.02);   // KE/PE0 at 2 s (toe on the base)
  EXPECT_NEAR(rows[10][4], 0.8632082188, 0.01);         // (|J_t|/|J_0|)_min at 1 s
  EXPECT_NEAR(rows[10][7] / 0.7148994595, 1.0, 0.02);   // εq,max at 1 s
  EXPECT_GT(rows[18][4], 0.0);                          // not yet inverted at 1.8 s
  EXPECT_LT(rows[19][4], 0.0);                          // inverted at 1.9 s
  const std::string summary = read_text(dir / "out" / "fem_summary.txt");
  EXPECT_NE(summary.find("last_time_in_zone = 1.300\n"), std::string::npos) << summary;
  EXPECT_NE(summary.find("zone_exit_time = 1.400\n"), std::string::npos) << summary;
  EXPECT_NE(summary.find("first_time_jacobian_ratio_negative = 1.900\n"), std::string::npos);
  // The first corner inversion (is_inverted, fem2mpm's refusal) comes at the same output.
  EXPECT_NE(summary.find("first_time_inverted = 1.900\n"), std::string::npos) << summary;
  EXPECT_GT(rows[18][10], 0.0);           // scaled_jacobian_min at 1.8 s
  EXPECT_LT(rows[19][10], 0.0);           // and at 1.9 s
  EXPECT_NEAR(rows[20][9], 0.919, 0.01);  // area ratio at 2 s (docs/method.md §3: 92 %)
}

TEST(FemSolveCli, CheckpointAtZoneExitKeepsTheLastStateInsideTheZone) {
  const fs::path dir = scratch("zone-exit");
  ColumnCase column;
  column.width = 20.0;
  column.height = 16.0;
  column.end_time = 1.5;
  column.checkpoint_every = 0.0;
  const fs::path case_file = write_case(dir, column.text());
  const ProgramRun run = fem_solve(
      case_file.string() + " -o " + (dir / "out").string() + " --no-vtk --checkpoint-at-zone-exit",
      dir);
  ASSERT_EQ(run.status, 0) << run.err;
  const std::string summary = read_text(dir / "out" / "fem_summary.txt");
  const auto at = summary.find("last_time_in_zone = ");
  ASSERT_NE(at, std::string::npos);
  const std::string last_inside = summary.substr(at + 20, summary.find('\n', at) - at - 20);
  ASSERT_NE(last_inside, "none") << summary;
  ASSERT_EQ(summary.find("zone_exit_time = none"), std::string::npos)
      << "the run never left the zone: lengthen it\n"
      << summary;
  const fs::path file = dir / "out" / ("fem_t" + last_inside + ".h5");
  ASSERT_TRUE(fs::exists(file)) << file;
  // The kept state is the state a run cut at that time ends with, every dataset equal.
  const ProgramRun cut = fem_solve(case_file.string() + " -o " + (dir / "cut").string() +
                                       " --no-vtk --quiet --until " + last_inside,
                                   dir);
  ASSERT_EQ(cut.status, 0) << cut.err;
  expect_identical(file, dir / "cut" / ("fem_t" + last_inside + ".h5"));
}

TEST(FemSolveCli, CheckpointEveryWritesExactlyTheMultiples) {
  // --checkpoint-every 0.15 on a case without checkpoint_every, outputs every 0.1 s, to
  // 0.4 s: checkpoints at 0 (geostatic), 0.15, 0.3 and the end time, nothing else; each
  // at its time exactly (the step before it is shortened to land on it).
  const fs::path dir = scratch("checkpoint-every");
  ColumnCase column;
  column.checkpoint_every = 0.0;
  const fs::path case_file = write_case(dir, column.text());
  const ProgramRun run = fem_solve(
      case_file.string() + " -o " + (dir / "out").string() + " --no-vtk -q --checkpoint-every 0.15",
      dir);
  ASSERT_EQ(run.status, 0) << run.err;
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(dir / "out")) {
    if (entry.path().extension() == ".h5") names.push_back(entry.path().filename().string());
  }
  std::sort(names.begin(), names.end());
  EXPECT_EQ(names, (std::vector<std::string>{"fem_t0.000.h5", "fem_t0.150.h5", "fem_t0.300.h5",
                                             "fem_t0.400.h5"}));
  for (const int k : {1, 2}) {
    const FemCheckpoint c =
        read_fem_checkpoint(dir / "out" / fmt::format("fem_t{:.3f}.h5", 0.15 * k));
    EXPECT_NEAR(c.header.time, 0.15 * k, 1e-12) << k;
  }
  // A checkpoint time is an output step too: the history has the rows of both grids.
  std::istringstream history(read_text(dir / "out" / "fem_history.csv"));
  std::string line;
  std::getline(history, line);
  std::vector<double> times;
  while (std::getline(history, line)) times.push_back(std::stod(line));
  const std::vector<double> expected{0.0, 0.1, 0.15, 0.2, 0.3, 0.4};
  ASSERT_EQ(times.size(), expected.size());
  for (std::size_t i = 0; i < times.size(); ++i) EXPECT_NEAR(times[i], expected[i], 1e-12);
}

TEST(FemSolveCli, InstabilityStopsWithoutWritingABadCheckpoint) {
  const fs::path dir = scratch("instability");
  ColumnCase column;
  column.time_step = 0.05;  // 13 times the Courant step
  const fs::path case_file = write_case(dir, column.text());
  const ProgramRun run =
      fem_solve(case_file.string() + " -o " + (dir / "out").string() + " --no-vtk", dir);
  expect_one_line_error(run, "instability: ");
  EXPECT_NE(run.err.find("the last good checkpoint is "), std::string::npos) << run.err;
  EXPECT_TRUE(fs::exists(dir / "out" / "fem_t0.000.h5"));
  EXPECT_FALSE(fs::exists(dir / "out" / "fem_t0.200.h5"));
}

/// Sets stress[0] of a checkpoint file to NaN behind the writer's back.
void poison_stress(const fs::path& file) {
  const hid_t h5 = H5Fopen(file.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  ASSERT_GE(h5, 0);
  const hid_t dataset = H5Dopen2(h5, "/gauss_points/stress", H5P_DEFAULT);
  ASSERT_GE(dataset, 0);
  const hid_t space = H5Dget_space(dataset);
  hsize_t dims[2] = {0, 0};
  H5Sget_simple_extent_dims(space, dims, nullptr);
  std::vector<double> values(static_cast<std::size_t>(dims[0] * dims[1]));
  H5Dread(dataset, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data());
  values[0] = std::nan("");
  H5Dwrite(dataset, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data());
  H5Sclose(space);
  H5Dclose(dataset);
  H5Fclose(h5);
}

TEST(FemSolveCli, UpdatedLagrangianStopsCleanlyWhenAnElementInverts) {
  // A state whose velocity field folds an element within one step, as if the body were
  // struck: its energy reference and the speed limit are raised so that the guard lets
  // it run, and the inversion must stop the run with that last good state kept.
  const fs::path dir = scratch("inversion");
  ColumnCase column;
  column.kinematics = "updated-lagrangian";
  column.extra_fem = "speed_limit_factor = 1e6\n";
  const fs::path case_file = write_case(dir, column.text());
  ASSERT_EQ(
      fem_solve(case_file.string() + " -q --no-vtk --until 0.2 -o " + (dir / "first").string(), dir)
          .status,
      0);
  FemCheckpoint struck = read_fem_checkpoint(dir / "first" / "fem_t0.200.h5");
  const std::size_t node = 12;  // an interior node of the 11 × 9 node grid
  struck.velocity[node] = Vec2(-2000.0, -2000.0);
  struck.solver["initial_energy"] = 1e12;
  write_checkpoint(dir / "struck" / "fem_t0.200.h5", struck);
  const ProgramRun run = fem_solve(case_file.string() + " --no-vtk -o " + (dir / "out").string() +
                                       " --restart " + (dir / "struck" / "fem_t0.200.h5").string(),
                                   dir);
  expect_one_line_error(run, "updated Lagrangian: element ");
  EXPECT_NE(run.err.find("inverts (det J ≤ 0) in the step from t = 0.200000 s"), std::string::npos)
      << run.err;
  const fs::path last_good = dir / "out" / "fem_t0.200.h5";
  ASSERT_TRUE(fs::exists(last_good));
  const FemCheckpoint kept = read_fem_checkpoint(last_good);
  EXPECT_EQ(kept.header.time, struck.header.time);
  EXPECT_EQ(kept.velocity[node], struck.velocity[node]);
  EXPECT_EQ(kept.displacement, struck.displacement);
  EXPECT_EQ(kept.stress, struck.stress);
}

class FemSolveBadInput : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = scratch(::testing::UnitTest::GetInstance()->current_test_info()->name());
    const fs::path good = write_case(dir_ / "good", ColumnCase{}.text());
    ASSERT_EQ(fem_solve(good.string() + " -q -o " + out().string() + " --until 0.2", dir_).status,
              0);
    before_ = snapshot(out());
  }
  void TearDown() override { EXPECT_EQ(snapshot(out()), before_) << "OUT was modified"; }

  fs::path out() const { return dir_ / "out"; }
  ProgramRun run_case(const std::string& text, const std::string& options = "") {
    const fs::path file = write_case(dir_ / "bad", text);
    return fem_solve(file.string() + " -o " + out().string() + " " + options, dir_);
  }

  fs::path dir_;
  std::map<std::string, std::string> before_;
};

// Issue 13: --checkpoint-every 0.0004 wrote several checkpoints under one name, among
// them fem_t0.000.h5, which then held t = 0.0004 instead of the geostatic state.
TEST_F(FemSolveBadInput, CheckpointCadenceFinerThanTheNames) {
  expect_one_line_error(run_case(ColumnCase{}.text(), "--checkpoint-every 0.0004"),
                        "--checkpoint-every = 0.0004 s is finer than the checkpoint names");
  expect_one_line_error(run_case(ColumnCase{}.text(), "--checkpoint-every 1e-12"),
                        "finer than the checkpoint names' 0.001 s");
}

// Issue 13: after the one-line "No space left on device" error, fem-solve crashed at
// exit inside HDF5's shutdown (status 139). Now: status 1, one line, no output left on
// the disk under a final or a temporary name.
TEST(FemSolveCli, AFullDiskIsOneLineAndACleanExit) {
  const fs::path dir = scratch("full-disk");
  const testing::SmallDisk disk(dir / "disk", 300);
  if (!disk.mounted()) GTEST_SKIP() << "needs root to mount a 300 KiB tmpfs";
  const fs::path case_file = fs::path(SLIDE_SOURCE_DIR) / "cases" / "column-short" / "case.toml";
  const ProgramRun run = fem_solve(
      case_file.string() + " -q --no-vtk --no-disk-check -o " + (dir / "disk" / "out").string(),
      dir);
  EXPECT_EQ(run.status, 1) << run.err;
  expect_one_line_error(run, "No space left on device");
  // The run's provenance (run.txt, inputs/, its log: written first, small) may stay; no
  // output, whole or partial.
  for (const auto& entry : fs::recursive_directory_iterator(dir / "disk")) {
    const bool provenance = entry.path().filename() == "run.txt" ||
                            entry.path().filename() == "fem-solve.log" ||
                            entry.path().parent_path().filename() == "inputs";
    EXPECT_TRUE(entry.is_directory() || provenance) << "left on the full disk: " << entry.path();
  }
}

TEST_F(FemSolveBadInput, ClockwiseBlockCorners) {
  ColumnCase column;
  column.mesh =
      "[mesh]\ngenerator = \"blocks\"\n[[mesh.blocks]]\ncorners = [[0.0, 0.0], [0.0, 8.0], "
      "[10.0, 8.0], [10.0, 0.0]]\ncells = [8, 10]\nmaterial = \"soil\"\n";
  expect_one_line_error(run_case(column.text()), "clockwise");
}

/// Two unit quads side by side in Gmsh 2.2 format with the surface "soil" and the
/// physical lines "left" and "right", but no "base".
const char* two_quads_without_base =
    "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n3\n1 1 \"left\"\n1 2 \"right\"\n"
    "2 3 \"soil\"\n$EndPhysicalNames\n$Nodes\n6\n1 0 0 0\n2 1 0 0\n3 2 0 0\n4 0 1 0\n5 1 1 0\n"
    "6 2 1 0\n$EndNodes\n$Elements\n4\n1 1 2 1 1 1 4\n2 1 2 2 2 3 6\n3 3 2 3 1 1 2 5 4\n"
    "4 3 2 3 1 2 3 6 5\n$EndElements\n";

std::string gmsh_case(const std::string& msh_name) {
  ColumnCase column;
  column.mesh = "[mesh]\ngenerator = \"gmsh\"\nfile = \"" + msh_name + "\"\n";
  column.geostatic_boundaries = "left = \"roller\"\nright = \"roller\"\nbase = \"roller\"\n";
  column.failure_boundaries = "left = \"roller\"\nright = \"free\"\nbase = \"friction\"\n";
  return column.text();
}

TEST_F(FemSolveBadInput, GmshFileWithoutTheBaseGroup) {
  write_file(dir_ / "bad" / "mesh.msh", two_quads_without_base);
  expect_one_line_error(run_case(gmsh_case("mesh.msh")), "has no physical group");
}

TEST_F(FemSolveBadInput, GmshFileWithAnInvertedElement) {
  // One counter-clockwise but re-entrant quad (an arrowhead: corner 3 lies inside the
  // triangle of the other three), so det J < 0 at that corner.
  write_file(dir_ / "bad" / "mesh.msh",
             "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n4\n1 1 \"left\"\n"
             "1 2 \"right\"\n1 3 \"base\"\n2 4 \"soil\"\n$EndPhysicalNames\n$Nodes\n4\n"
             "1 0 0 0\n2 1 0 0\n3 0.2 0.2 0\n4 0 1 0\n$EndNodes\n$Elements\n4\n"
             "1 1 2 1 1 1 4\n2 1 2 2 2 2 3\n3 1 2 3 3 1 2\n4 3 2 4 1 1 2 3 4\n$EndElements\n");
  // Element 4 on line 23; its centre is the mean of its nodes, and det J at the reflex
  // corner 2 is ((x2 − x3) × (x2 − x1))/4 = ((0.2, −0.8) × (−0.8, 0.2))/4 = −0.15.
  expect_one_line_error(run_case(gmsh_case("mesh.msh")),
                        "mesh.msh:23: element 4 at (0.3, 0.3) is inverted or has zero area: det J "
                        "= -0.15 at its corner 2 (node 3 at (0.2, 0.2))");
}

TEST_F(FemSolveBadInput, RestartFromAParticleFile) {
  ParticleCheckpoint particles;
  particles.header.kind = CheckpointKind::particles;
  particles.header.case_name = "test-column";
  particles.particles.resize(1);
  particles.particles.volume[0] = 1.0;
  particles.particles.mass[0] = 1700.0;
  particles.particles.size[0] = Vec2(1.0, 1.0);
  particles.materials = {synthetic::soil(MaterialModel::mohr_coulomb)};
  const fs::path file = dir_ / "particles.h5";
  write_checkpoint(file, particles);
  expect_one_line_error(run_case(ColumnCase{}.text(), "--restart " + file.string()),
                        "kind is \"particles\"");
}

TEST_F(FemSolveBadInput, RestartFromACheckpointHoldingNaN) {
  const fs::path file = dir_ / "nan" / "fem_t0.200.h5";
  fs::create_directories(file.parent_path());
  fs::copy_file(out() / "fem_t0.200.h5", file);
  poison_stress(file);
  expect_one_line_error(run_case(ColumnCase{}.text(), "--restart " + file.string()), file.string());
}

TEST_F(FemSolveBadInput, RestartFromAMissingFile) {
  expect_one_line_error(run_case(ColumnCase{}.text(), "--restart " + (dir_ / "none.h5").string()),
                        "none.h5");
}

TEST_F(FemSolveBadInput, RestartAtTheEndTime) {
  expect_one_line_error(
      run_case(ColumnCase{}.text(), "--until 0.2 --restart " + (out() / "fem_t0.200.h5").string()),
      "at or after the end time");
}

TEST_F(FemSolveBadInput, RestartWithAnotherElementType) {
  ColumnCase column;
  column.element = "tri3";
  expect_one_line_error(run_case(column.text(), "--restart " + (out() / "fem_t0.200.h5").string()),
                        "quad4-1gp elements but the case asks for tri3");
}

TEST_F(FemSolveBadInput, MissingCaseFile) {
  const ProgramRun run =
      fem_solve((dir_ / "missing.toml").string() + " -o " + out().string(), dir_);
  expect_one_line_error(run, "missing.toml");
}

TEST_F(FemSolveBadInput, UnknownOption) {
  const ProgramRun run = fem_solve(
      (dir_ / "good" / "case.toml").string() + " -o " + out().string() + " --no-such-option", dir_);
  EXPECT_EQ(run.status, 2);
  EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << run.err;
}

}  // namespace
}  // namespace slide::fem
