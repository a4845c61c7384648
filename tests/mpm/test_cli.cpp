// mpm-solve as users and scripts see it: restart bit for bit, bad particle files, particles
// leaving the grid, the summary line, the instability guard.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include <gtest/gtest.h>
#include <hdf5.h>
#include <vtkDataArray.h>
#include <vtkFieldData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkSmartPointer.h>
#include <vtkType.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridReader.h>

#include "common/io/checkpoint.hpp"
#include "tests/support/mpm_builders.hpp"
#include "tests/support/programs.hpp"
#include "tests/support/pvd.hpp"

namespace slide::mpm {
namespace {

namespace fs = std::filesystem;

const fs::path solver_program = fs::path(SLIDE_BINARY_DIR) / "bin" / "mpm-solve";

/// A 10 m × 8 m frictional column on a 30 m × 10 m grid, 2 × 2 particles per cell.
std::string small_case(const std::string& mpm_extra = "", double end_time = 0.5) {
  return fmt::format(R"(
[case]
name = "small-column"
description = "mpm-solve command-line tests"

[[materials]]
name = "soil"
model = "mohr-coulomb"
density = 1700.0
youngs_modulus = 23.8e6
poisson_ratio = 0.23
friction_angle = 22.2
cohesion = 1000.0

[mesh]
generator = "profile"
element_size = 1.0
surface = [[0.0, 8.0], [10.0, 8.0]]
material = "soil"

[fem]
end_time = 1.0
friction_coefficient = 0.466

[fem.geostatic.boundaries]
left = "roller"
right = "roller"
base = "roller"

[fem.failure.boundaries]
left = "roller"
right = "free"
base = "friction"

[transfer]
main_time = 0.0
sweep_times = [0.0]

[mpm]
domain = [[0.0, 0.0], [30.0, 10.0]]
cell_size = 1.0
end_time = {}
checkpoint_every = 0.25
output_every = 0.05
friction_coefficient = 0.466
particles_per_cell = [2, 2]
{}

[mpm.boundaries]
left = "roller"
right = "roller"
base = "friction"
top = "free"

[metrics]
initial_length = 10.0
initial_height = 8.0
)",
                     end_time, mpm_extra);
}

using slide::testing::ProgramRun;
using slide::testing::read_text;

/// Runs mpm-solve with `arguments` in `folder`, capturing stdout and stderr.
ProgramRun run_solver(const fs::path& folder, const std::string& arguments) {
  return slide::testing::run_program(solver_program.string() + " " + arguments, folder);
}

fs::path fresh_folder(const std::string& name) {
  return slide::testing::fresh_folder(fs::path(SLIDE_BINARY_DIR) / "tests" / "mpm" / "cli" / name);
}

fs::path write_case(const fs::path& folder, const std::string& text) {
  slide::testing::write_file(folder / "case.toml", text);
  return folder / "case.toml";
}

/// (An empty vector's data() may be null, which memcmp must not be given even for 0 bytes.)
template <class T>
bool same_bits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() &&
         (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

/// The run of case `c` in two parts, to 0.25 s and then on from its checkpoint, into `split`.
void run_split(const fs::path& folder, const fs::path& c, const fs::path& split) {
  const ProgramRun first =
      run_solver(folder, fmt::format("{} -o {} --until 0.25 --quiet", c.string(), split.string()));
  ASSERT_EQ(first.status, 0) << first.err;
  const ProgramRun second =
      run_solver(folder, fmt::format("{} -o {} --restart {} --quiet", c.string(), split.string(),
                                     (split / "mpm_t0.250.h5").string()));
  ASSERT_EQ(second.status, 0) << second.err;
}

TEST(MpmSolveCli, RestartContinuesBitForBit) {
  const fs::path folder = fresh_folder("restart");
  const fs::path c = write_case(folder, small_case());
  const ProgramRun straight = run_solver(
      folder, fmt::format("{} -o {} --quiet", c.string(), (folder / "straight").string()));
  ASSERT_EQ(straight.status, 0) << straight.err;
  EXPECT_NE(straight.out.find("summary: steps="), std::string::npos) << straight.out;
  EXPECT_NE(straight.out.find("particle_steps_per_s="), std::string::npos) << straight.out;

  const fs::path split = folder / "split";
  run_split(folder, c, split);

  const ParticleCheckpoint a = read_particle_checkpoint(folder / "straight" / "mpm_final.h5");
  const ParticleCheckpoint b = read_particle_checkpoint(split / "mpm_final.h5");
  EXPECT_EQ(a.header.time, b.header.time);
  EXPECT_EQ(a.header.step, b.header.step);
  EXPECT_TRUE(same_bits(a.particles.coordinates, b.particles.coordinates));
  EXPECT_TRUE(same_bits(a.particles.velocity, b.particles.velocity));
  EXPECT_TRUE(same_bits(a.particles.stress, b.particles.stress));
  EXPECT_TRUE(same_bits(a.particles.strain, b.particles.strain));
  EXPECT_TRUE(same_bits(a.particles.volume, b.particles.volume));
  EXPECT_TRUE(same_bits(a.particles.id, b.particles.id));
  EXPECT_EQ(read_text(folder / "straight" / "mpm_history.csv"),
            read_text(split / "mpm_history.csv"));
  // The history has the docs/contract.md columns.
  const std::string history = read_text(split / "mpm_history.csv");
  EXPECT_EQ(history.substr(0, history.find('\n')),
            "time,kinetic_energy,pe0,ke_over_pe0,x_toe,runout,runout_normalised,x_front_95,"
            "max_speed");
}

/// The header and the rows of a recorder's CSV.
std::pair<std::vector<std::string>, std::vector<std::vector<double>>> read_recorder(
    const fs::path& file) {
  std::istringstream text(read_text(file));
  std::string line, cell;
  std::getline(text, line);
  std::vector<std::string> header;
  std::istringstream names(line);
  while (std::getline(names, cell, ',')) header.push_back(cell);
  std::vector<std::vector<double>> rows;
  while (std::getline(text, line)) {
    std::istringstream values(line);
    rows.emplace_back();
    while (std::getline(values, cell, ','))
      rows.back().push_back(std::strtod(cell.c_str(), nullptr));
  }
  return {header, rows};
}

TEST(MpmSolveCli, RecordersFollowTheParticleThatStartedNearestTheirPointThroughARestart) {
  const fs::path folder = fresh_folder("recorders");
  const Vec2 point(9.7, 7.9);  // the column's top corner, which collapses
  const fs::path c =
      write_case(folder, small_case("[[mpm.recorders]]\nname = \"corner\"\npoints = [[9.7, 7.9]]\n"
                                    "every = 0.1\n"));
  const ProgramRun straight = run_solver(
      folder, fmt::format("{} -o {} --quiet", c.string(), (folder / "straight").string()));
  ASSERT_EQ(straight.status, 0) << straight.err;
  const fs::path split = folder / "split";
  run_split(folder, c, split);
  EXPECT_EQ(read_text(folder / "straight" / "recorders" / "corner.csv"),
            read_text(split / "recorders" / "corner.csv"));

  // The particle followed: the one whose x − u at the start is nearest the point.
  const ParticleCheckpoint start = read_particle_checkpoint(split / "mpm_t0.000.h5");
  std::size_t nearest = 0;
  for (std::size_t p = 0; p < start.particles.count(); ++p) {
    const auto distance = [&](std::size_t q) {
      return (start.particles.coordinates[q] - start.particles.displacement[q] - point).norm();
    };
    if (distance(p) < distance(nearest)) nearest = p;
  }
  const std::int64_t id = start.particles.id[nearest];
  const auto [header, rows] = read_recorder(split / "recorders" / "corner.csv");
  ASSERT_EQ(header.size(), 12u);
  EXPECT_EQ(header[1], fmt::format("p{}_x", id));
  EXPECT_EQ(header[11], fmt::format("p{}_eq", id));
  // A row at the start and one at the first step end at or after each 0.1 s, to the end.
  ASSERT_EQ(rows.size(), 6u);
  EXPECT_EQ(rows.front()[0], 0.0);
  EXPECT_EQ(rows.back()[0], 0.5);
  for (std::size_t r = 1; r < rows.size(); ++r) {
    EXPECT_GE(rows[r][0], 0.1 * static_cast<double>(r) - 1e-12);
    EXPECT_LT(rows[r][0], 0.1 * static_cast<double>(r) + 0.02);
  }
  // The last row is the particle's state in the final checkpoint, digit for digit.
  const ParticleCheckpoint end = read_particle_checkpoint(split / "mpm_final.h5");
  const auto at = std::ranges::find(end.particles.id, id) - end.particles.id.begin();
  ASSERT_LT(static_cast<std::size_t>(at), end.particles.count());
  const auto p = static_cast<std::size_t>(at);
  const std::vector<double>& last = rows.back();
  EXPECT_EQ(last[1], end.particles.coordinates[p].x());
  EXPECT_EQ(last[2], end.particles.coordinates[p].y());
  EXPECT_EQ(last[3], end.particles.displacement[p].x());
  EXPECT_EQ(last[4], end.particles.displacement[p].y());
  EXPECT_EQ(last[5], end.particles.velocity[p].x());
  EXPECT_EQ(last[8], end.particles.stress[p][1]);
  EXPECT_EQ(last[11], end.particles.eps_q[p]);
  // The corner moved: the record is of a particle in the collapse, not a resting one.
  EXPECT_GT(std::hypot(last[3], last[4]), 0.05);
}

using slide::testing::pvd_entries;

std::vector<double> times_of(const std::vector<std::pair<double, std::string>>& entries) {
  std::vector<double> times;
  for (const auto& entry : entries) times.push_back(std::round(entry.first * 1e6) / 1e6);
  return times;
}

// The VTK cadence: mpm.vtk_every = 0.15 s on outputs every 0.05 s gives frames at 0.15 and
// 0.3 and 0.45, plus the start, the checkpoint at 0.25 and the end at 0.5; --vtk-every
// overrides it; a cadence off the output steps is refused, from the case file or the
// command line; a restart writes the frames of the uninterrupted run. Each frame, read
// back with VTK, carries its time, the pressure of its stress and typed integer arrays.
TEST(MpmSolveCli, VtkFramesFollowTheCadenceAndCarryTheirTime) {
  const fs::path folder = fresh_folder("vtk-cadence");
  const fs::path c = write_case(folder, small_case("vtk_every = 0.15"));
  const ProgramRun run =
      run_solver(folder, fmt::format("{} -o {} --quiet", c.string(), (folder / "case").string()));
  ASSERT_EQ(run.status, 0) << run.err;
  const auto frames = pvd_entries(folder / "case" / "mpm.pvd");
  EXPECT_EQ(times_of(frames), (std::vector<double>{0.0, 0.15, 0.25, 0.3, 0.45, 0.5}));

  const ProgramRun option = run_solver(folder, fmt::format("{} -o {} --quiet --vtk-every 0.1",
                                                           c.string(), (folder / "cli").string()));
  ASSERT_EQ(option.status, 0) << option.err;
  EXPECT_EQ(times_of(pvd_entries(folder / "cli" / "mpm.pvd")),
            (std::vector<double>{0.0, 0.1, 0.2, 0.25, 0.3, 0.4, 0.5}));

  const ProgramRun off_grid = run_solver(
      folder, fmt::format("{} -o {} --vtk-every 0.07", c.string(), (folder / "off").string()));
  EXPECT_EQ(off_grid.status, 1);
  EXPECT_NE(off_grid.err.find("--vtk-every = 0.07 s is not a whole multiple"), std::string::npos)
      << off_grid.err;
  const fs::path bad = write_case(folder / "bad", small_case("vtk_every = 0.07"));
  const ProgramRun bad_case =
      run_solver(folder, fmt::format("{} -o {}", bad.string(), (folder / "bad-out").string()));
  EXPECT_EQ(bad_case.status, 1);
  EXPECT_NE(bad_case.err.find("mpm.vtk_every"), std::string::npos) << bad_case.err;

  const fs::path split = folder / "split";
  run_split(folder, c, split);
  EXPECT_EQ(read_text(split / "mpm.pvd"), read_text(folder / "case" / "mpm.pvd"));

  for (const auto& [time, file] : frames) {
    SCOPED_TRACE(file);
    vtkNew<vtkXMLUnstructuredGridReader> reader;
    reader->SetFileName((folder / "case" / file).c_str());
    reader->Update();
    vtkUnstructuredGrid* grid = reader->GetOutput();
    ASSERT_NE(grid, nullptr);
    ASSERT_NE(grid->GetFieldData()->GetArray("TimeValue"), nullptr);
    EXPECT_EQ(grid->GetFieldData()->GetArray("TimeValue")->GetTuple1(0), time);
    vtkPointData* data = grid->GetPointData();
    for (const char* name : {"material_id", "id", "element", "active", "stress", "stress_tensor",
                             "strain_tensor", "pressure", "von_mises_stress"}) {
      ASSERT_NE(data->GetArray(name), nullptr) << name;
    }
    EXPECT_EQ(data->GetArray("material_id")->GetDataType(), VTK_TYPE_INT32);
    EXPECT_EQ(data->GetArray("id")->GetDataType(), VTK_TYPE_INT64);
    EXPECT_EQ(data->GetArray("active")->GetDataType(), VTK_TYPE_UINT8);
    vtkDataArray* stress = data->GetArray("stress");
    vtkDataArray* pressure = data->GetArray("pressure");
    for (vtkIdType p = 0; p < grid->GetNumberOfPoints(); p += 37) {
      const double trace =
          stress->GetComponent(p, 0) + stress->GetComponent(p, 1) + stress->GetComponent(p, 2);
      EXPECT_NEAR(pressure->GetTuple1(p), -trace / 3.0, 1e-9 * std::abs(trace) + 1e-9) << p;
    }
  }
}

// Issue 13: mpm.time_step = 1e-300 and E = 1e300 (a Courant step of 1e-149 s) hung
// mpm-solve. It now refuses a run of more than 10⁹ steps before it starts, naming what
// made the step small, and writes nothing.
TEST(MpmSolveCli, RefusesARunThatWouldNeverEnd) {
  const fs::path folder = fresh_folder("never-ending");
  const auto expect_refused = [&](std::string text, const std::string& from, const std::string& to,
                                  const std::string& cause) {
    const auto at = text.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    text.replace(at, from.size(), to);
    const fs::path c = write_case(folder, text);
    const fs::path out = folder / "out";
    const ProgramRun r = run_solver(folder, c.string() + " -q --no-vtk -o " + out.string());
    EXPECT_EQ(r.status, 1) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_NE(r.err.find("steps of"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(cause), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(out)) << "a refused run wrote " << out;
  };
  expect_refused(small_case("time_step = 1e-300\n"), "time_step = 1e-300", "time_step = 1e-300",
                 "mpm.time_step is too small");
  expect_refused(small_case(), "youngs_modulus = 23.8e6", "youngs_modulus = 1e300",
                 "p-wave speed c = sqrt(M V / m) is");
}

// Issue 13: --restart and --particles from another case only warned (fem-solve refuses).
// Now a one-line error, unless --other-case says it is meant (a warning then).
TEST(MpmSolveCli, RefusesTheFilesOfAnotherCaseUnlessAsked) {
  const fs::path folder = fresh_folder("other-case");
  const fs::path first = write_case(folder, small_case("", 0.1));
  ASSERT_EQ(
      run_solver(folder, first.string() + " -q --no-vtk -o " + (folder / "a").string()).status, 0);
  std::string other = small_case("", 0.2);
  const std::string name = "name = \"small-column\"";
  other.replace(other.find(name), name.size(), "name = \"other-column\"");
  const fs::path second = write_case(folder / "other", other);
  const std::string checkpoint = (folder / "a" / "mpm_final.h5").string();
  for (const std::string option : {"--restart ", "--particles "}) {
    const ProgramRun refused =
        run_solver(folder, second.string() + " -q --no-vtk -o " + (folder / "b").string() + " " +
                               option + checkpoint);
    EXPECT_EQ(refused.status, 1) << option << refused.err;
    EXPECT_EQ(std::count(refused.err.begin(), refused.err.end(), '\n'), 1) << refused.err;
    EXPECT_NE(refused.err.find("written for case \"small-column\", not for case \"other-column\""),
              std::string::npos)
        << refused.err;
    EXPECT_FALSE(fs::exists(folder / "b"));
  }
  const ProgramRun asked =
      run_solver(folder, second.string() + " -q --no-vtk --other-case -o " +
                             (folder / "c").string() + " --restart " + checkpoint);
  EXPECT_EQ(asked.status, 0) << asked.err;
  EXPECT_NE(asked.err.find("(--other-case)"), std::string::npos) << asked.err;
}

// Issue 13: negative steps_since_sort and a NaN or negative previous step were read
// without complaint (the NaN surfaced later as a "non-finite position"). Each damaged
// /solver value is now one line naming it, before anything is written.
TEST(MpmSolveCli, ARestartNamesADamagedSolverValue) {
  const fs::path folder = fresh_folder("damaged-solver");
  const fs::path c = write_case(folder, small_case("", 0.1));
  ASSERT_EQ(run_solver(folder, c.string() + " -q --no-vtk -o " + (folder / "a").string()).status,
            0);
  const ParticleCheckpoint good = read_particle_checkpoint(folder / "a" / "mpm_final.h5");
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<std::pair<std::string, SettingValue>> damages{
      {"previous_time_step", nan},
      {"previous_time_step", -1e-3},
      {"steps_since_sort", std::int64_t{-1}},
      {"rest_timer", -1.0},
      {"reference_height", nan},
      {"energy_scale", -5.0},
      {"initial_energy", std::numeric_limits<double>::infinity()}};
  for (const auto& [key, value] : damages) {
    ParticleCheckpoint bad = good;
    bad.solver[key] = value;
    const fs::path file = folder / "bad.h5";
    write_checkpoint(file, bad);
    const fs::path out = folder / "out";
    const ProgramRun r = run_solver(
        folder, c.string() + " -q --no-vtk -o " + out.string() + " --restart " + file.string());
    EXPECT_EQ(r.status, 1) << key << ": " << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_NE(r.err.find("/solver attribute " + key), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(out)) << key;
  }
}

TEST(MpmSolveCli, MultiYieldInMpmKeepsItsSurfacesAndRestartsBitForBit) {
  // Pure MPM with the multi-yield model in MPM: the switch freezes every particle's
  // strength from its K0 confinement; the strengths and the 20 surfaces per particle go
  // through the checkpoint, sorting and the restart, and keep adding up to the deviator.
  const fs::path folder = fresh_folder("restart-multi-yield");
  std::string text = small_case();
  const std::string from = "model = \"mohr-coulomb\"";
  text.replace(text.find(from), from.size(), "model = \"pressure-independent-multi-yield\"");
  const fs::path c = write_case(folder, text);
  const ProgramRun straight = run_solver(
      folder, fmt::format("{} -o {} --quiet", c.string(), (folder / "straight").string()));
  ASSERT_EQ(straight.status, 0) << straight.err;
  const fs::path split = folder / "split";
  run_split(folder, c, split);
  const ParticleCheckpoint a = read_particle_checkpoint(folder / "straight" / "mpm_final.h5");
  const ParticleCheckpoint b = read_particle_checkpoint(split / "mpm_final.h5");
  EXPECT_TRUE(same_bits(a.particles.stress, b.particles.stress));
  EXPECT_TRUE(same_bits(a.particles.coordinates, b.particles.coordinates));
  ASSERT_EQ(a.particles.surface_stress.per_point, 20u);
  EXPECT_TRUE(same_bits(a.particles.surface_stress.values, b.particles.surface_stress.values));
  for (std::size_t p = 0; p < a.particles.count(); ++p) {
    ASSERT_EQ(a.particles.state[p].peak_strength, b.particles.state[p].peak_strength);
    ASSERT_GT(a.particles.state[p].peak_strength, 0.0) << "frozen at the switch";
    const Vec4& sigma = a.particles.stress[p];
    const double mean = (sigma[0] + sigma[1] + sigma[2]) / 3.0;
    Vec4 sum = Vec4::Zero();
    for (const Vec4& s : a.particles.surface_stress.of(p)) sum += s;
    const Vec4 deviator(sigma[0] - mean, sigma[1] - mean, sigma[2] - mean, sigma[3]);
    ASSERT_LT((sum - deviator).cwiseAbs().maxCoeff(), 1e-6 * (1.0 + sigma.cwiseAbs().maxCoeff()))
        << p;
  }
}

/// The small case scaled to a 40 m × 16 m column, 4 × 4 particles per cell (10,240
/// particles) on an 80 m × 20 m grid: above the 8,192 particles from which the kernels
/// run in parallel.
std::string parallel_case(const std::string& mpm_extra = "", double end_time = 0.5) {
  std::string text = small_case(mpm_extra, end_time);
  auto replace = [&](const std::string& from, const std::string& to) {
    const auto at = text.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    text.replace(at, from.size(), to);
  };
  replace("surface = [[0.0, 8.0], [10.0, 8.0]]", "surface = [[0.0, 16.0], [40.0, 16.0]]");
  replace("domain = [[0.0, 0.0], [30.0, 10.0]]", "domain = [[0.0, 0.0], [80.0, 20.0]]");
  replace("particles_per_cell = [2, 2]", "particles_per_cell = [4, 4]");
  replace("initial_length = 10.0", "initial_length = 40.0");
  replace("initial_height = 8.0", "initial_height = 16.0");
  return text;
}

// The same above the parallel threshold on 2 threads: 0 → 0.25 → 0.5 equals 0 → 0.5 file
// for file, byte for byte (the writer stores no time stamps), history included.
TEST(MpmSolveCli, RestartContinuesBitForBitOnTheParallelPath) {
  const fs::path folder = fresh_folder("restart_parallel");
  const fs::path c = write_case(folder, parallel_case());
  const ProgramRun straight =
      run_solver(folder, fmt::format("{} -o {} --threads 2 --no-vtk --quiet", c.string(),
                                     (folder / "straight").string()));
  ASSERT_EQ(straight.status, 0) << straight.err;
  EXPECT_NE(straight.out.find("particles=10240"), std::string::npos) << straight.out;
  const fs::path split = folder / "split";
  const ProgramRun first =
      run_solver(folder, fmt::format("{} -o {} --until 0.25 --threads 2 --no-vtk --quiet",
                                     c.string(), split.string()));
  ASSERT_EQ(first.status, 0) << first.err;
  const ProgramRun second = run_solver(
      folder, fmt::format("{} -o {} --restart {} --threads 2 --no-vtk --quiet", c.string(),
                          split.string(), (split / "mpm_t0.250.h5").string()));
  ASSERT_EQ(second.status, 0) << second.err;

  const fs::path a = folder / "straight" / "mpm_final.h5", b = split / "mpm_final.h5";
  const ParticleCheckpoint state = read_particle_checkpoint(a);
  ASSERT_GT(state.particles.count(), 8192u);
  EXPECT_EQ(state.header.time, 0.5);
  // It moved across cells (the sort reordered it), not a body at rest.
  double largest = 0.0;
  for (const Vec2& u : state.particles.displacement) largest = std::max(largest, u.norm());
  EXPECT_GT(largest, 0.5);
  EXPECT_EQ(read_text(a), read_text(b));
  EXPECT_EQ(read_text(folder / "straight" / "mpm_t0.500.h5"), read_text(split / "mpm_t0.500.h5"));
  EXPECT_EQ(read_text(folder / "straight" / "mpm_history.csv"),
            read_text(split / "mpm_history.csv"));
}

// APIC: the affine velocities are particle state. They go through the checkpoints
// (/particles/affine_velocity), the sort and the restart: 0 → 0.25 → 0.5 equals 0 → 0.5
// file for file, byte for byte, on the serial path (the small case) and above the
// parallel threshold on 2 threads. A restart under flip-pic drops them and says so.
TEST(MpmSolveCli, ApicRestartContinuesBitForBit) {
  const std::string apic = "velocity_transfer = \"apic\"";
  for (const bool parallel : {false, true}) {
    const fs::path folder = fresh_folder(parallel ? "restart_apic_parallel" : "restart_apic");
    const fs::path c = write_case(folder, parallel ? parallel_case(apic) : small_case(apic));
    const std::string options = "--threads 2 --no-vtk --quiet";
    const ProgramRun straight = run_solver(
        folder, fmt::format("{} -o {} {}", c.string(), (folder / "straight").string(), options));
    ASSERT_EQ(straight.status, 0) << straight.err;
    const fs::path split = folder / "split";
    const ProgramRun first = run_solver(
        folder, fmt::format("{} -o {} --until 0.25 {}", c.string(), split.string(), options));
    ASSERT_EQ(first.status, 0) << first.err;
    const ProgramRun second =
        run_solver(folder, fmt::format("{} -o {} --restart {} {}", c.string(), split.string(),
                                       (split / "mpm_t0.250.h5").string(), options));
    ASSERT_EQ(second.status, 0) << second.err;

    const fs::path a = folder / "straight" / "mpm_final.h5", b = split / "mpm_final.h5";
    const ParticleCheckpoint state = read_particle_checkpoint(a);
    EXPECT_EQ(state.particles.count() > 8192u, parallel);
    ASSERT_EQ(state.particles.affine_velocity.size(), state.particles.count());
    double largest = 0.0;
    for (const Vec4& v : state.particles.affine_velocity)
      largest = std::max(largest, v.cwiseAbs().maxCoeff());
    EXPECT_GT(largest, 1e-3) << "the collapse has affine velocities, m²/s";
    EXPECT_EQ(std::get<std::string>(state.solver.at("velocity_transfer")), "apic");
    EXPECT_EQ(read_text(a), read_text(b));
    EXPECT_EQ(read_text(folder / "straight" / "mpm_t0.500.h5"), read_text(split / "mpm_t0.500.h5"));
    EXPECT_EQ(read_text(folder / "straight" / "mpm_history.csv"),
              read_text(split / "mpm_history.csv"));
    if (parallel) continue;
    // The same checkpoint continued under flip-pic: refused as a changed case, then allowed
    // (--allow-changed algorithms) with a warning, and no affine state written.
    const fs::path flip = write_case(folder, small_case());
    const std::string restart_flip =
        fmt::format("{} -o {} --restart {} --no-vtk --quiet", flip.string(),
                    (folder / "flip").string(), (split / "mpm_t0.250.h5").string());
    const ProgramRun refused = run_solver(folder, restart_flip);
    EXPECT_EQ(refused.status, 1);
    EXPECT_NE(refused.err.find("the case's algorithms changed"), std::string::npos) << refused.err;
    const ProgramRun switched = run_solver(folder, restart_flip + " --allow-changed algorithms");
    ASSERT_EQ(switched.status, 0) << switched.err;
    EXPECT_NE(switched.err.find("apic (PIC share 0) smoothing cell, exit freeze → gimp musl "
                                "flip-pic"),
              std::string::npos)
        << switched.err;
    EXPECT_TRUE(read_particle_checkpoint(folder / "flip" / "mpm_final.h5")
                    .particles.affine_velocity.empty());
  }
}

/// Overwrites one value of a dataset, as a foreign tool could (our writer refuses).
void patch_value(const fs::path& file, const char* dataset, hsize_t row, hsize_t column,
                 double value) {
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  const hid_t d = H5Dopen2(f, dataset, H5P_DEFAULT);
  ASSERT_GE(d, 0);
  const hid_t space = H5Dget_space(d);
  const int rank = H5Sget_simple_extent_ndims(space);
  hsize_t start[2] = {row, column}, count[2] = {1, 1};
  H5Sselect_hyperslab(space, H5S_SELECT_SET, start, nullptr, count, nullptr);
  const hsize_t one = 1;
  const hid_t memory = H5Screate_simple(1, &one, nullptr);
  (void)rank;
  EXPECT_GE(H5Dwrite(d, H5T_NATIVE_DOUBLE, memory, space, H5P_DEFAULT, &value), 0);
  H5Sclose(memory);
  H5Sclose(space);
  H5Dclose(d);
  H5Fclose(f);
}

TEST(MpmSolveCli, BadParticleFilesAreOneLineErrorsNamingTheParticle) {
  const fs::path folder = fresh_folder("bad_input");
  const fs::path c = write_case(folder, small_case());
  ASSERT_EQ(run_solver(folder, fmt::format("{} -o {} --until 0 --quiet --no-vtk", c.string(),
                                           (folder / "t0").string()))
                .status,
            0);
  const ParticleCheckpoint good = read_particle_checkpoint(folder / "t0" / "mpm_t0.000.h5");

  auto particle_file = [&](const std::string& name, auto&& damage) {
    ParticleCheckpoint bad = good;
    bad.header.kind = CheckpointKind::particles;
    bad.solver.clear();
    damage(bad);
    const fs::path path = folder / (name + ".h5");
    write_checkpoint(path, bad);
    return path;
  };
  auto expect_rejected = [&](const fs::path& file, const std::string& what,
                             const std::string& particle) {
    const ProgramRun r =
        run_solver(folder, fmt::format("{} -o {} --particles {} --no-vtk", c.string(),
                                       (folder / "out").string(), file.string()));
    EXPECT_NE(r.status, 0) << what;
    // One error line (a warning may precede it), naming the particle and the problem.
    std::istringstream lines(r.err);
    int errors = 0;
    for (std::string line; std::getline(lines, line);) {
      if (line.rfind("mpm-solve: error: ", 0) != 0) continue;
      ++errors;
      EXPECT_NE(line.find(particle), std::string::npos) << what << ": " << line;
      EXPECT_NE(line.find(what), std::string::npos) << line;
    }
    EXPECT_EQ(errors, 1) << what << ": " << r.err;
  };

  expect_rejected(
      particle_file("outside",
                    [](ParticleCheckpoint& p) { p.particles.coordinates[5] = Vec2(45.0, 3.0); }),
      "outside the grid", "particle 5");
  // A material the case does not have: refused by the material tables, before any
  // particle is looked at (their masses were computed with the file's densities).
  expect_rejected(particle_file("material",
                                [](ParticleCheckpoint& p) {
                                  p.materials.push_back(p.materials[0]);
                                  p.materials[1].name = "other";
                                  p.particles.material_id[7] = 1;
                                }),
                  "has 2 materials, the case 1", "material.h5");
  const fs::path nan_velocity = particle_file("nan_velocity", [](ParticleCheckpoint&) {});
  patch_value(nan_velocity, "/particles/velocity", 3, 0, std::numeric_limits<double>::quiet_NaN());
  expect_rejected(nan_velocity, "velocity", "particle 3");
  const fs::path zero_mass = particle_file("zero_mass", [](ParticleCheckpoint&) {});
  patch_value(zero_mass, "/particles/mass", 4, 0, 0.0);
  expect_rejected(zero_mass, "mass", "particle 4");
}

/// The warnings of mpm-solve's stderr that mention particles leaving the grid.
std::vector<std::string> exit_warnings(const std::string& err) {
  std::vector<std::string> lines;
  std::istringstream in(err);
  for (std::string line; std::getline(in, line);) {
    if (line.find("left the grid") != std::string::npos) lines.push_back(line);
  }
  return lines;
}

/// Particles thrown upwards out of the grid's free top: frozen (kept, velocity 0, at the
/// end of the arrays) or removed. They are thrown at speeds from 30 to 50 m/s, so they
/// leave on many different steps; the warnings are rate-limited (the first exit, then one
/// per checkpoint, checkpoints every 0.25 s here) and the last one gives the run's total.
// The case's pure-MPM particles at t = 0 (a run to --until 0), as a particle file to
// edit and start from.
ParticleCheckpoint starting_particles(const fs::path& folder, const fs::path& case_file) {
  const ProgramRun r =
      run_solver(folder, fmt::format("{} -o {} --until 0 --quiet --no-vtk", case_file.string(),
                                     (folder / "t0").string()));
  if (r.status != 0) throw std::runtime_error("the run to t = 0 failed: " + r.err);
  ParticleCheckpoint file = read_particle_checkpoint(folder / "t0" / "mpm_t0.000.h5");
  file.header.kind = CheckpointKind::particles;
  file.solver.clear();
  return file;
}

TEST(MpmSolveCli, ParticlesLeavingTheGridAreFrozenOrRemovedWithAWarning) {
  for (const std::string mode : {"freeze", "remove"}) {
    const fs::path folder = fresh_folder("exit_" + mode);
    const fs::path c =
        write_case(folder, small_case(fmt::format("particle_exit = \"{}\"", mode), 0.3));
    ParticleCheckpoint file = starting_particles(folder, c);
    std::size_t thrown = 0;
    for (std::size_t k = 0; k < file.particles.count(); ++k) {
      if (file.particles.coordinates[k].y() > 7.0 && file.particles.coordinates[k].x() < 2.0) {
        file.particles.velocity[k] = Vec2(0.0, 30.0 + 5.0 * static_cast<double>(thrown % 5));
        ++thrown;
      }
    }
    ASSERT_GT(thrown, 0u);
    write_checkpoint(folder / "thrown.h5", file);
    const ProgramRun r =
        run_solver(folder, fmt::format("{} -o {} --particles {} --no-vtk --quiet", c.string(),
                                       (folder / "out").string(), (folder / "thrown.h5").string()));
    ASSERT_EQ(r.status, 0) << r.err;
    const ParticleCheckpoint final_state =
        read_particle_checkpoint(folder / "out" / "mpm_final.h5");
    const auto frozen = std::get<std::int64_t>(final_state.solver.at("frozen_particles"));
    std::size_t left = 0;
    if (mode == "freeze") {
      EXPECT_EQ(final_state.particles.count(), file.particles.count());
      EXPECT_GT(frozen, 0);
      left = static_cast<std::size_t>(frozen);
      for (std::size_t k = final_state.particles.count() - static_cast<std::size_t>(frozen);
           k < final_state.particles.count(); ++k) {
        EXPECT_EQ(final_state.particles.velocity[k], Vec2::Zero());
        EXPECT_GE(final_state.particles.coordinates[k].y(), 10.5);
      }
    } else {
      EXPECT_LT(final_state.particles.count(), file.particles.count());
      EXPECT_EQ(frozen, 0);
      left = file.particles.count() - final_state.particles.count();
    }
    // The first exit at once; at most one more per checkpoint (0.25 s) and the end; the
    // total last.
    const std::vector<std::string> warnings = exit_warnings(r.err);
    ASSERT_GE(warnings.size(), 2u) << r.err;
    EXPECT_LE(warnings.size(), 4u) << r.err;
    EXPECT_NE(warnings.front().find("left the grid at t = "), std::string::npos) << r.err;
    const std::string fate = mode == "freeze" ? "were frozen" : "were removed";
    EXPECT_NE(warnings.front().find(fate), std::string::npos) << r.err;
    EXPECT_NE(
        warnings.back().find(fmt::format("warning: {} particles left the grid in this run", left)),
        std::string::npos)
        << r.err;
  }
}

// A body whose front reaches the grid's far edge (+x) is warned of at the end: its
// runout would be the grid's. The same body left alone (the column spreads a few metres
// on a 30 m grid) is not.
TEST(MpmSolveCli, ABodyEndingAtTheGridsFarEdgeIsWarnedOf) {
  const fs::path folder = fresh_folder("far_edge");
  const fs::path c = write_case(folder, small_case("", 0.9));
  ParticleCheckpoint file = starting_particles(folder, c);
  write_checkpoint(folder / "still.h5", file);
  // The whole body thrown at 25 m/s: its front reaches the wall 20 m away at 0.8 s.
  for (Vec2& v : file.particles.velocity) v = Vec2(25.0, 0.0);
  write_checkpoint(folder / "thrown.h5", file);
  const std::string warning = "warning: the body ends against the grid's far edge (x = 30 m";
  for (const std::string name : {"still", "thrown"}) {
    const ProgramRun r = run_solver(
        folder, fmt::format("{} -o {} --particles {} --no-vtk --quiet", c.string(),
                            (folder / name).string(), (folder / (name + ".h5")).string()));
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_EQ(r.err.find(warning) != std::string::npos, name == "thrown") << name << r.err;
  }
}

TEST(MpmSolveCli, InstabilityStopsWithADiagnosisAndKeepsTheLastCheckpoint) {
  const fs::path folder = fresh_folder("unstable");
  // Ten times the stable step.
  const fs::path c = write_case(folder, small_case("time_step = 0.04"));
  const ProgramRun r = run_solver(
      folder, fmt::format("{} -o {} --no-vtk --quiet", c.string(), (folder / "out").string()));
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.err.find("instability"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("last good checkpoint"), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_TRUE(fs::exists(folder / "out" / "mpm_t0.000.h5"));
  EXPECT_FALSE(fs::exists(folder / "out" / "mpm_final.h5"));
}

}  // namespace
}  // namespace slide::mpm

namespace slide::mpm {
namespace {

// Pure MPM with the elastic gravity stage: at t = 0 the body is at rest, undisplaced, and
// carries roughly the lithostatic stress; the switch to the plastic model is logged.
TEST(MpmSolveCli, GravityStageGivesARestingLithostaticStart) {
  const fs::path folder = fresh_folder("gravity_stage");
  // Elastic soil, so that the switch leaves the stresses of the gravity stage as they are.
  std::string text = small_case(
      "initial_stress = \"gravity\"\n"
      "gravity_stage_duration = 1.5\n"
      "gravity_stage_damping = 0.7");
  text.replace(text.find("mohr-coulomb"), 12, "linear-elastic");
  for (const char* key : {"friction_angle = 22.2\n", "cohesion = 1000.0\n"}) {
    text.erase(text.find(key), std::string(key).size());
  }
  const fs::path c = write_case(folder, text);
  const ProgramRun r = run_solver(
      folder, fmt::format("{} -o {} --until 0 --no-vtk", c.string(), (folder / "out").string()));
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("elastic gravity stage"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("returned to the yield surface"), std::string::npos) << r.out;
  const ParticleCheckpoint t0 = read_particle_checkpoint(folder / "out" / "mpm_t0.000.h5");
  EXPECT_EQ(t0.header.time, 0.0);
  double weight = 0.0, base_force = 0.0;
  for (std::size_t k = 0; k < t0.particles.count(); ++k) {
    EXPECT_EQ(t0.particles.velocity[k], Vec2::Zero());
    EXPECT_EQ(t0.particles.displacement[k], Vec2::Zero());
    weight += t0.particles.mass[k] * 9.81;
    // σyy integrated over the bottom row of cells ≈ the weight the base carries.
    if (t0.particles.coordinates[k].y() < 1.0)
      base_force -= t0.particles.stress[k][1] * t0.particles.volume[k];
  }
  // Σ σyy V over the bottom row of cells is the row's mean σyy times its area: the
  // weight above its mid-height, (H − h/2)/H of the body's weight.
  EXPECT_NEAR(base_force / weight, (8.0 - 0.5) / 8.0, 0.05);
}

}  // namespace
}  // namespace slide::mpm

namespace slide::mpm {
namespace {

/// The particles case `c` starts from at t = 0 (mpm-solve --until 0 into `folder`/t0), as
/// a particle file to be edited and written for --particles.
ParticleCheckpoint initial_particle_file(const fs::path& folder, const fs::path& c) {
  const ProgramRun t0 = run_solver(folder, fmt::format("{} -o {} --until 0 --quiet --no-vtk",
                                                       c.string(), (folder / "t0").string()));
  EXPECT_EQ(t0.status, 0) << t0.err;
  ParticleCheckpoint file = read_particle_checkpoint(folder / "t0" / "mpm_t0.000.h5");
  file.header.kind = CheckpointKind::particles;
  file.solver.clear();
  return file;
}

/// (time, KE/PE0) of every row of an mpm_history.csv.
std::vector<std::pair<double, double>> ke_over_pe0_rows(const fs::path& history_file) {
  std::vector<std::pair<double, double>> rows;
  std::istringstream history(read_text(history_file));
  std::string line;
  std::getline(history, line);  // header
  while (std::getline(history, line)) {
    std::vector<double> row;
    std::istringstream cells(line);
    for (std::string cell; std::getline(cells, cell, ',');) row.push_back(std::stod(cell));
    rows.emplace_back(row.at(0), row.at(3));
  }
  return rows;
}

// The rest criterion on a body that has to come to rest first: the small column,
// launched sliding at v0 = 3 m/s towards +x (KE/PE0 = v0²/(g H0) = 0.11 at t = 0),
// collapses and is stopped by the base friction and its own plastic flow (at about
// 3.3 s; with APIC, as the cases run: pure FLIP's particle noise alone holds KE/PE0 near
// 2.5·10⁻³ on this coarse grid, so that column never comes to rest). The run must
// stop once KE/PE0 has stayed below θ = 10⁻³ for 0.2 s: not while the body still moves
// (a timer that ignored the motion or did not restart would fire at about 0.2 s), and
// not at the end time (a criterion that never fires). The stop comes `rest_duration`
// after the last history row above θ, to one output interval (0.05 s, the rows are that
// far apart) and a step.
TEST(MpmSolveCli, StopsWhenAtRest) {
  const double threshold = 1e-3, duration = 0.2, end_time = 6.0, output_every = 0.05;
  const fs::path folder = fresh_folder("rest");
  const fs::path c = write_case(
      folder, small_case(fmt::format("velocity_transfer = \"apic\"\nrest_threshold = {}\n"
                                     "rest_duration = {}",
                                     threshold, duration),
                         end_time));
  ParticleCheckpoint launched = initial_particle_file(folder, c);
  for (Vec2& v : launched.particles.velocity) v = Vec2(3.0, 0.0);
  write_checkpoint(folder / "launched.h5", launched);
  const ProgramRun r =
      run_solver(folder, fmt::format("{} -o {} --particles {} --vtk-every 1", c.string(),
                                     (folder / "out").string(), (folder / "launched.h5").string()));
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("at rest"), std::string::npos) << r.out;
  const double stop = read_particle_checkpoint(folder / "out" / "mpm_final.h5").header.time;
  // The state it stopped in is also the last VTK frame, although off the 1 s cadence.
  const auto frames = pvd_entries(folder / "out" / "mpm.pvd");
  ASSERT_FALSE(frames.empty());
  EXPECT_NEAR(frames.back().first, stop, 1e-9);

  const auto rows = ke_over_pe0_rows(folder / "out" / "mpm_history.csv");
  ASSERT_GE(rows.size(), 2u);
  EXPECT_GT(rows.front().second, 100 * threshold) << "the body must start moving";
  double last_moving = -1.0;
  for (const auto& [t, ratio] : rows) {
    if (ratio >= threshold) last_moving = t;
  }
  ASSERT_GT(last_moving, 0.5) << "the motion must take a while to decay";
  EXPECT_EQ(rows.back().first, stop);  // the stop writes its row
  EXPECT_GT(stop, last_moving + duration);
  EXPECT_LT(stop, last_moving + duration + output_every + 0.005);
  EXPECT_LT(stop, end_time - duration);
  RecordProperty("motion_decayed_s", fmt::format("{:.2f}", last_moving));
  RecordProperty("stop_s", fmt::format("{:.4f}", stop));
}

/// An elastic layer 25 m × 1 m on a roller base, fixed at x = 0, free at x = 25 m and on
/// top, vibrating in its first mode v = v0 sin(πx/2L): a bar in plane strain whose top is
/// free, ω = (π/2L) sqrt(E/((1 − ν²)ρ)) (the layer is thin against the wavelength). Its
/// kinetic energy KE_max cos²(ωt) dips to zero twice per period; with the particle file's
/// pe0 set to KE_max, KE/PE0 falls below θ for windows of 2 arcsin(√θ)/ω and rises above
/// it again in between. Writes the particle file; returns the window length.
double vibrating_layer_file(const fs::path& folder, const fs::path& c, double threshold) {
  ParticleCheckpoint file = initial_particle_file(folder, c);
  const double length = 25.0, v0 = 0.5;
  double kinetic = 0.0;
  for (std::size_t k = 0; k < file.particles.count(); ++k) {
    const double x = file.particles.coordinates[k].x();
    const double v = v0 * std::sin(std::numbers::pi * x / (2 * length));
    file.particles.velocity[k] = Vec2(v, 0.0);
    kinetic += 0.5 * file.particles.mass[k] * v * v;
  }
  file.header.pe0 = kinetic;
  write_checkpoint(folder / "layer.h5", file);
  const Material& m = file.materials.at(0);
  const double omega =
      std::numbers::pi / (2 * length) *
      std::sqrt(m.youngs_modulus / ((1 - m.poisson_ratio * m.poisson_ratio) * m.density));
  return 2 * std::asin(std::sqrt(threshold)) / omega;
}

std::string vibrating_layer_case(double threshold, double duration) {
  std::string text =
      small_case(fmt::format("rest_threshold = {}\nrest_duration = {}\noutput_every = 0.01",
                             threshold, duration),
                 1.0);
  auto replace = [&](const std::string& from, const std::string& to) {
    const auto at = text.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    text.replace(at, from.size(), to);
  };
  replace("mohr-coulomb", "linear-elastic");
  replace("friction_angle = 22.2\n", "");
  replace("cohesion = 1000.0\n", "");
  replace("surface = [[0.0, 8.0], [10.0, 8.0]]", "surface = [[0.0, 1.0], [25.0, 1.0]]");
  replace("domain = [[0.0, 0.0], [30.0, 10.0]]", "domain = [[0.0, 0.0], [32.0, 4.0]]");
  replace("output_every = 0.05\n", "");
  replace("left = \"roller\"\nright = \"roller\"\nbase = \"friction\"\ntop = \"free\"",
          "left = \"fixed\"\nright = \"free\"\nbase = \"roller\"\ntop = \"free\"");
  return text;
}

/// Windows of KE/PE0 < θ in mpm_history.csv: their count, their total length (from the
/// rows, 0.01 s apart), and the first one's start and end (interpolated between rows).
struct BelowWindows {
  int count = 0;
  double total = 0.0;
  double first_start = -1.0, first_end = -1.0;
};

BelowWindows windows_below(const fs::path& history_file, double threshold) {
  BelowWindows w;
  double t_previous = -1.0, ratio_previous = 0.0;
  bool below_previous = false;
  for (const auto& [t, ratio] : ke_over_pe0_rows(history_file)) {
    const bool below = ratio < threshold;
    const double crossing =
        t_previous + (t - t_previous) * (ratio_previous - threshold) / (ratio_previous - ratio);
    if (below && !below_previous && t_previous >= 0.0) {
      ++w.count;
      if (w.count == 1) w.first_start = crossing;
    }
    if (!below && below_previous && w.count == 1 && w.first_end < 0.0) w.first_end = crossing;
    if (below && below_previous) w.total += t - t_previous;
    t_previous = t;
    ratio_previous = ratio;
    below_previous = below;
  }
  return w;
}

// The rest timer counts only uninterrupted time below the threshold. A rest duration of
// 1.5 windows is never reached within one window, so the run goes on to its end although
// its windows add up to more than that (a timer that did not restart when KE/PE0 rose
// again would have stopped it); one of half a window stops the run half a window after
// the first one began.
TEST(MpmSolveCli, RestTimerRestartsWhenTheKineticEnergyRisesAgain) {
  const double threshold = 0.1;
  const fs::path folder = fresh_folder("rest_timer");
  const double window = vibrating_layer_file(
      folder, write_case(folder, vibrating_layer_case(threshold, 0)), threshold);
  auto run = [&](double duration, const std::string& name) {
    const fs::path c = write_case(folder, vibrating_layer_case(threshold, duration));
    return run_solver(folder,
                      fmt::format("{} -o {} --particles {} --no-vtk", c.string(),
                                  (folder / name).string(), (folder / "layer.h5").string()));
  };

  const double long_duration = 1.5 * window;
  const ProgramRun reset = run(long_duration, "long");
  ASSERT_EQ(reset.status, 0) << reset.err;
  EXPECT_EQ(reset.out.find("at rest"), std::string::npos) << reset.out;
  EXPECT_EQ(read_particle_checkpoint(folder / "long" / "mpm_final.h5").header.time, 1.0);
  const BelowWindows w = windows_below(folder / "long" / "mpm_history.csv", threshold);
  EXPECT_GE(w.count, 2);
  EXPECT_GT(w.total, long_duration);
  // The windows are the layer's: the first one as long as 2 arcsin(√θ)/ω (to 3 %).
  EXPECT_NEAR((w.first_end - w.first_start) / window, 1.0, 0.03);

  const double short_duration = 0.5 * window;
  const ProgramRun rest = run(short_duration, "short");
  ASSERT_EQ(rest.status, 0) << rest.err;
  EXPECT_NE(rest.out.find("at rest"), std::string::npos) << rest.out;
  // The same motion up to there: it stops in the first window, `short_duration` after
  // its start, to the step (3.9 ms) and the interpolation between history rows.
  const double stop = read_particle_checkpoint(folder / "short" / "mpm_final.h5").header.time;
  EXPECT_GT(stop, w.first_start + short_duration - 0.002);
  EXPECT_LT(stop, w.first_start + short_duration + 0.006);
}

}  // namespace
}  // namespace slide::mpm
