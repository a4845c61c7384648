// fem2mpm as users and Makefiles run it: build/bin/fem2mpm on FE checkpoints written
// with the checkpoint module. Good input gives a particle file and its JSON report,
// bit-identical from run to run; bad input gives one line on stderr, a non-zero exit
// status and no output file.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <sstream>
#include <string>
#include <thread>

#include <gtest/gtest.h>
#include <hdf5.h>
#include <sys/wait.h>
#include <unistd.h>

#include "common/io/checkpoint.hpp"
#include "tests/support/programs.hpp"
#include "tools/synthetic/fem_checkpoints.hpp"

namespace slide {
namespace {

namespace fs = std::filesystem;

using testing::ProgramRun;
using testing::read_text;

std::size_t count_lines(const std::string& text) {
  std::size_t lines = 0;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) ++lines;
  return lines;
}

class Fem2mpm : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    folder_ = testing::fresh_folder(fs::path(SLIDE_BINARY_DIR) / "tests" / "transfer" / "cli" /
                                    info->name());
  }

  fs::path file(const std::string& name) const { return folder_ / name; }

  ProgramRun run(const std::string& arguments) const {
    return testing::run_program(std::string(SLIDE_BINARY_DIR) + "/bin/fem2mpm " + arguments,
                                folder_);
  }

  /// Files in the folder other than the captured output (temporary files must not stay).
  std::size_t files_besides_logs() const {
    std::size_t n = 0;
    for (const auto& entry : fs::directory_iterator(folder_)) {
      const auto name = entry.path().filename().string();
      if (name != "stdout.txt" && name != "stderr.txt") ++n;
    }
    return n;
  }

  /// Runs with bad input: a one-line error, a non-zero status, no particle file.
  void expect_refused(const std::string& arguments, const std::string& message_part) {
    const std::size_t before = files_besides_logs();
    const ProgramRun r = run(arguments);
    EXPECT_NE(r.status, 0) << r.err;
    EXPECT_EQ(count_lines(r.err), 1u) << r.err;
    EXPECT_NE(r.err.find(message_part), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(file("particles.h5")));
    EXPECT_FALSE(fs::exists(file("particles.transfer.json")));
    EXPECT_EQ(files_besides_logs(), before) << "a temporary or partial file was left behind";
  }

  fs::path folder_;
};

FemCheckpoint geostatic_checkpoint() {
  synthetic::BlockFields fields;
  fields.stress = synthetic::geostatic_stress(1700.0, 0.23, 2.0);
  fields.velocity = [](const Vec2& x) { return Vec2(0.1 * x.y(), 0.0); };
  return synthetic::make_block(8, 8, 2.0, 2.0, ElementType::quad4_1gp, fields);
}

TEST_F(Fem2mpm, WritesTheParticleFileAndTheReport) {
  write_checkpoint(file("fem.h5"), geostatic_checkpoint());
  const ProgramRun r = run(file("fem.h5").string() + " -o " + file("particles.h5").string());
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(r.err.empty()) << r.err;
  EXPECT_NE(r.out.find("mass"), std::string::npos) << r.out;
  const ParticleCheckpoint particles = read_particle_checkpoint(file("particles.h5"));
  EXPECT_EQ(particles.header.kind, CheckpointKind::particles);
  EXPECT_EQ(particles.header.time, 2.0);
  EXPECT_EQ(particles.header.case_name, "transfer-test");
  EXPECT_EQ(particles.particles.count(), 64u * 16u);
  EXPECT_EQ(particles.transfer.particles_per_element, "4x4");
  EXPECT_EQ(particles.transfer.stress_interpolation, "rbf");
  EXPECT_EQ(particles.transfer.rbf_polynomial, "none");
  EXPECT_NEAR(particles.transfer.rbf_shape, std::sqrt(1.75 * 1.75 / 64.0), 1e-15);
  const std::string json = read_text(file("particles.transfer.json"));
  EXPECT_NE(json.find("\"particles\": 1024"), std::string::npos) << json;
  EXPECT_NE(json.find("\"input\": \"" + file("fem.h5").string() + "\""), std::string::npos);
}

TEST_F(Fem2mpm, OptionsReachTheParticleFileAndQuietPrintsNothing) {
  write_checkpoint(file("fem.h5"), geostatic_checkpoint());
  const ProgramRun r = run(file("fem.h5").string() + " -o " + file("particles.h5").string() +
                           " --particles-per-element 3x2 --stress-interpolation rbf-local"
                           " --rbf-neighbours 9 --rbf-polynomial none --rbf-shape 0.3 --quiet");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;
  const ParticleCheckpoint particles = read_particle_checkpoint(file("particles.h5"));
  EXPECT_EQ(particles.particles.count(), 64u * 6u);
  EXPECT_EQ(particles.transfer.particles_per_element, "3x2");
  EXPECT_EQ(particles.transfer.stress_interpolation, "rbf-local");
  EXPECT_EQ(particles.transfer.rbf_polynomial, "none");
  EXPECT_EQ(particles.transfer.rbf_shape, 0.3);
  EXPECT_EQ(particles.transfer.rbf_neighbours, 9);
}

TEST_F(Fem2mpm, CaseFileGivesDefaultsAndFlagsOverrideThem) {
  write_checkpoint(file("fem.h5"), geostatic_checkpoint());
  const std::string case_file = std::string(SLIDE_SOURCE_DIR) + "/cases/column-short/case.toml";
  const ProgramRun r = run(file("fem.h5").string() + " -o " + file("particles.h5").string() +
                           " --case " + case_file + " --stress-interpolation element --quiet");
  ASSERT_EQ(r.status, 0) << r.err;
  const ParticleCheckpoint particles = read_particle_checkpoint(file("particles.h5"));
  EXPECT_EQ(particles.transfer.particles_per_element, "4x4");     // from the case
  EXPECT_EQ(particles.transfer.stress_interpolation, "element");  // from the flag
}

TEST_F(Fem2mpm, SameInputGivesTheSameFileBitForBit) {
  write_checkpoint(file("fem.h5"), geostatic_checkpoint());
  for (const char* method : {"rbf", "rbf-local"}) {
    const std::string args = file("fem.h5").string() + " --quiet --stress-interpolation " + method;
    ASSERT_EQ(run(args + " -o " + file("a.h5").string()).status, 0);
    // Across a clock second: HDF5 would otherwise stamp object headers with the time.
    std::this_thread::sleep_for(std::chrono::milliseconds(1100));
    ASSERT_EQ(run(args + " -o " + file("b.h5").string()).status, 0);
    const std::string a = read_text(file("a.h5")), b = read_text(file("b.h5"));
    EXPECT_GT(a.size(), 1000u);
    EXPECT_TRUE(a == b) << method << ": the two particle files differ";
  }
}

/// Overwrites one dataset of an HDF5 file in place, as a damaged or foreign file would.
void poison_dataset(const fs::path& path, const char* dataset_path) {
  const hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  const hid_t d = H5Dopen2(f, dataset_path, H5P_DEFAULT);
  ASSERT_GE(d, 0);
  const hid_t space = H5Dget_space(d);
  const auto n = static_cast<std::size_t>(H5Sget_simple_extent_npoints(space));
  std::vector<double> values(n, 0.0);
  ASSERT_GE(H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()), 0);
  values[n / 2] = std::numeric_limits<double>::quiet_NaN();
  ASSERT_GE(H5Dwrite(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()), 0);
  H5Sclose(space);
  H5Dclose(d);
  H5Fclose(f);
}

// Issue 13: "fem2mpm X.h5 -o X.h5" replaced its own input with particles.
TEST_F(Fem2mpm, RefusesToWriteOverItsInput) {
  write_checkpoint(file("fem.h5"), geostatic_checkpoint());
  const std::string before = read_text(file("fem.h5"));
  const ProgramRun r = run(file("fem.h5").string() + " -o " + file("fem.h5").string());
  EXPECT_NE(r.status, 0);
  EXPECT_EQ(count_lines(r.err), 1u) << r.err;
  EXPECT_NE(r.err.find("is the FE checkpoint being read"), std::string::npos) << r.err;
  EXPECT_EQ(read_text(file("fem.h5")), before);
  // Also through another spelling of the same path.
  const ProgramRun dotted =
      run(file("fem.h5").string() + " -o " + (folder_ / "." / "fem.h5").string());
  EXPECT_NE(dotted.status, 0);
  EXPECT_EQ(read_text(file("fem.h5")), before);
}

// A killed run's temporary (its process gone) is removed at the next start; the
// temporary of a live process stays.
TEST_F(Fem2mpm, RemovesTheTemporariesOfKilledRuns) {
  write_checkpoint(file("fem.h5"), geostatic_checkpoint());
  // Above the kernel's largest pid (4194304), so no process can have it.
  std::ofstream(file(".particles.h5.tmp-999999999")) << "cut";
  const std::string live = ".other.h5.tmp-" + std::to_string(::getpid());
  std::ofstream(file(live)) << "being written";
  const ProgramRun r = run(file("fem.h5").string() + " -o " + file("particles.h5").string());
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_FALSE(fs::exists(file(".particles.h5.tmp-999999999")));
  EXPECT_TRUE(fs::exists(file(live)));
  EXPECT_NE(r.out.find("removed 1 temporary file(s) that killed runs left"), std::string::npos)
      << r.out;
}

TEST_F(Fem2mpm, RefusesNanStressesInOneLine) {
  write_checkpoint(file("fem.h5"), geostatic_checkpoint());
  poison_dataset(file("fem.h5"), "/gauss_points/stress");
  expect_refused(file("fem.h5").string() + " -o " + file("particles.h5").string(),
                 "/gauss_points/stress");
}

TEST_F(Fem2mpm, RefusesAnInvertedElementUnlessAllowed) {
  FemCheckpoint fem = synthetic::make_block(3, 3, 3.0, 3.0, ElementType::quad4_1gp);
  const auto top_right = static_cast<std::size_t>(fem.mesh.element(4)[2]);
  fem.coordinates[top_right] = Vec2(0.5, 0.5);
  fem.displacement[top_right] = fem.coordinates[top_right] - fem.mesh.nodes[top_right];
  for (Index e = 0; e < fem.mesh.element_count(); ++e) {
    fem.volume[static_cast<std::size_t>(e)] =
        element_area(ElementShape::quad4, fem.mesh.element_nodes(e, fem.coordinates));
  }
  write_checkpoint(file("fem.h5"), fem);
  expect_refused(file("fem.h5").string() + " -o " + file("particles.h5").string(),
                 "element 4 is inverted");
  const ProgramRun r = run(file("fem.h5").string() + " -o " + file("particles.h5").string() +
                           " --allow-inverted --quiet");
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.err.find("inverted element(s) transferred"), std::string::npos) << r.err;
  EXPECT_TRUE(fs::exists(file("particles.h5")));
  EXPECT_NE(read_text(file("particles.transfer.json")).find("\"inverted_elements\": [4, "),
            std::string::npos);
}

TEST_F(Fem2mpm, RefusesTheWrongKindOfFile) {
  write_checkpoint(file("fem.h5"), geostatic_checkpoint());
  ASSERT_EQ(run(file("fem.h5").string() + " --quiet -o " + file("first.h5").string()).status, 0);
  fs::remove(file("first.transfer.json"));
  expect_refused(file("first.h5").string() + " -o " + file("particles.h5").string(), "fem");
  std::ofstream(file("notes.txt")) << "not an HDF5 file\n";
  expect_refused(file("notes.txt").string() + " -o " + file("particles.h5").string(), "notes.txt");
}

/// The number after "key": in a flat JSON report (the test's own small reader).
double json_value(const std::string& json, const std::string& key) {
  const auto at = json.find("\"" + key + "\": ");
  if (at == std::string::npos) {
    ADD_FAILURE() << "no " << key << " in the report";
    return std::numeric_limits<double>::quiet_NaN();
  }
  return std::stod(json.substr(at + key.size() + 4));
}

// The transfer check on the real case: fem-solve's geostatic state of
// cases/geostatic-4x4 (0.25 m one-point quads) through fem2mpm at 4 × 4 particles.
// σyy against −ρg(H − y): the plain multiquadric within 0.5 % of ρgH at the particles at
// least one element from the boundary and within 5 % everywhere (it extrapolates beyond
// the outermost Gauss points: measured 0.28 % and 1.93 %); with the linear polynomial
// (rbf and rbf-local) within 1e-6 ρgH at every particle. Mass, volume and momentum of
// the report against the FE model, every key of the report present.
TEST_F(Fem2mpm, GeostaticCaseThroughFemSolveAndFem2mpm) {
  const fs::path fem_solve = fs::path(SLIDE_BINARY_DIR) / "bin" / "fem-solve";
  if (!fs::exists(fem_solve)) GTEST_SKIP() << "fem-solve is not built";
  const std::string case_file = std::string(SLIDE_SOURCE_DIR) + "/cases/geostatic-4x4/case.toml";
  const std::string command = fem_solve.string() + " " + case_file + " -o " + file("fem").string() +
                              " --quiet --no-vtk > " + file("fem-solve.txt").string() + " 2>&1";
  ASSERT_EQ(std::system(command.c_str()), 0) << read_text(file("fem-solve.txt"));
  const fs::path checkpoint = file("fem") / "fem_t0.000.h5";
  const FemCheckpoint fem = read_fem_checkpoint(checkpoint);
  const double rho = 1700.0, g = 9.81, height = 4.0, rho_g_h = rho * g * height;

  struct Errors {
    double interior = 0.0, everywhere = 0.0;
  };
  auto transfer = [&](const std::string& name, const std::string& options) {
    const ProgramRun r = run(checkpoint.string() + " -o " + file(name).string() + " " + options);
    EXPECT_EQ(r.status, 0) << r.err;
    EXPECT_TRUE(r.err.empty()) << "no warning expected: " << r.err;
    return read_particle_checkpoint(file(name)).particles;
  };
  auto errors = [&](const Particles& particles) {
    Errors e;
    for (std::size_t p = 0; p < particles.count(); ++p) {
      const Vec2 x = particles.coordinates[p];
      const double error = std::abs(particles.stress[p][1] + rho * g * (height - x.y())) / rho_g_h;
      e.everywhere = std::max(e.everywhere, error);
      const bool inside = x.x() > 0.25 && x.x() < 3.75 && x.y() > 0.25 && x.y() < 3.75;
      if (inside) e.interior = std::max(e.interior, error);
    }
    return e;
  };
  const Particles plain = transfer("rbf.h5", "");
  const Errors e_plain = errors(plain);
  std::cout << "geostatic-4x4, rbf (none): max |σyy error| / ρgH " << e_plain.interior
            << " interior, " << e_plain.everywhere << " everywhere\n";
  EXPECT_LT(e_plain.interior, 0.005);
  EXPECT_LT(e_plain.everywhere, 0.05);
  EXPECT_EQ(plain.count(), 256u * 16u);

  const Particles linear = transfer("rbf-linear.h5", "--rbf-polynomial linear");
  const Particles local = transfer("rbf-local.h5", "--stress-interpolation rbf-local");
  EXPECT_LT(errors(linear).everywhere, 1e-6);
  EXPECT_LT(errors(local).everywhere, 1e-6);
  double agreement = 0.0;
  for (std::size_t p = 0; p < linear.count(); ++p) {
    agreement =
        std::max(agreement, (linear.stress[p] - local.stress[p]).cwiseAbs().maxCoeff() / rho_g_h);
  }
  EXPECT_LT(agreement, 1e-6) << "rbf and rbf-local, both linear";

  // The report of the default run: every key, and the conservation figures.
  const std::string json = read_text(file("rbf.transfer.json"));
  for (const char* key : {"input",
                          "output",
                          "case",
                          "time",
                          "element_type",
                          "elements",
                          "gauss_points",
                          "particles",
                          "particles_per_element",
                          "particle_rule",
                          "stress_interpolation",
                          "rbf_polynomial",
                          "rbf_shape",
                          "rbf_neighbours",
                          "condition_estimate",
                          "factorisations",
                          "reduced_polynomial",
                          "residual_stress_max",
                          "residual_stress_rms",
                          "residual_relative_max",
                          "mass_fe",
                          "mass_particles",
                          "volume_fe",
                          "volume_particles",
                          "momentum_fe_nodal",
                          "momentum_fe_element",
                          "momentum_particles",
                          "kinetic_energy_fe_nodal",
                          "kinetic_energy_fe_element",
                          "kinetic_energy_particles",
                          "inverted_elements",
                          "collapsed_volume_ratio",
                          "collapsed_elements",
                          "excluded_gauss_points",
                          "clamped_plastic_strain",
                          "limited_particles",
                          "limited_stress_particles",
                          "seconds_interpolation",
                          "seconds_total"}) {
    EXPECT_NE(json.find("\"" + std::string(key) + "\": "), std::string::npos) << key;
  }
  const double mass = rho * 16.0;
  EXPECT_NEAR(json_value(json, "mass_fe"), mass, 1e-12 * mass);
  EXPECT_NEAR(json_value(json, "mass_particles"), mass, 1e-12 * mass);
  EXPECT_NEAR(json_value(json, "volume_fe"), 16.0, 1e-12 * 16.0);
  EXPECT_NEAR(json_value(json, "volume_particles"), 16.0, 1e-12 * 16.0);
  EXPECT_EQ(json_value(json, "kinetic_energy_particles"), 0.0);
  EXPECT_EQ(json_value(json, "particles"), 4096.0);
  EXPECT_NEAR(json_value(json, "rbf_shape"), std::sqrt(3.75 * 3.75 / 256.0), 1e-12);
  EXPECT_LT(json_value(json, "residual_relative_max"), 1e-8);
  EXPECT_EQ(json_value(json, "limited_particles"), 0.0) << "round-off is no overshoot";
  EXPECT_GT(json_value(json, "condition_estimate"), 1.0);
  EXPECT_EQ(fem.header.time, 0.0);
}

TEST_F(Fem2mpm, RefusesBadOptionsInOneLine) {
  write_checkpoint(file("fem.h5"), geostatic_checkpoint());
  const std::string io = file("fem.h5").string() + " -o " + file("particles.h5").string();
  expect_refused(io + " --stress-interpolation spline", "--stress-interpolation");
  expect_refused(io + " --particles-per-element 0", "--particles-per-element");
  expect_refused(io + " --rbf-shape -1", "--rbf-shape");
  expect_refused(file("missing.h5").string() + " -o " + file("particles.h5").string(),
                 "missing.h5");
}

// The pipeline check of the issue: rbf and rbf-local on the column-short FE states
// (docs/method.md §7) at t = 1 s and t = 2 s. Runs fem-solve to 2 s (about a second), so it
// skips where fem-solve is not built. By t = 2 s the small-strain FE mesh has entangled
// at the toe (fem-solve reports (|J_t|/|J_0|)_min < 0 from about 1.9 s): that checkpoint
// needs --allow-inverted, and there the two interpolations differ at the toe (see
// transfer/README.md, "Collapsed elements").
TEST_F(Fem2mpm, RbfAndRbfLocalOnColumnShort) {
  const fs::path fem_solve = fs::path(SLIDE_BINARY_DIR) / "bin" / "fem-solve";
  if (!fs::exists(fem_solve)) GTEST_SKIP() << "fem-solve is not built";
  // The FE state of Mohr–Coulomb without damping (the case's FE model before the
  // multi-yield soil), whose stress field and toe folding this test was written for.
  std::string text = read_text(fs::path(SLIDE_SOURCE_DIR) / "cases/column-short/case.toml");
  for (const auto& [from, to] :
       {std::pair<std::string, std::string>{"fem_model = \"pressure-independent-multi-yield\"",
                                            "fem_model = \"mohr-coulomb\""},
        {"rayleigh_stiffness = 0.005626", "rayleigh_stiffness = 0.0"}}) {
    const auto at = text.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    text.replace(at, from.size(), to);
  }
  const std::string case_file = file("case.toml").string();
  {
    std::ofstream out(case_file);
    out << text;
  }
  const std::string command = fem_solve.string() + " " + case_file + " -o " + file("fem").string() +
                              " --until 2 > " + file("fem-solve.txt").string() + " 2>&1";
  ASSERT_EQ(std::system(command.c_str()), 0) << read_text(file("fem-solve.txt"));
  const double rho_g_h0 = 1700.0 * 9.81 * 40.0;

  struct Difference {
    double max = 0.0;
    double p99 = 0.0;       // 99th percentile over the particles
    std::size_t above = 0;  // particles differing by more than 1 % of ρgH0
  };
  auto compare = [&](const std::string& time, const std::string& extra) {
    const fs::path checkpoint = file("fem") / ("fem_t" + time + ".h5");
    auto particles = [&](const std::string& method, const std::string& name) {
      const ProgramRun r = run(checkpoint.string() + " -o " + file(name).string() +
                               " --quiet --stress-interpolation " + method + " " + extra);
      EXPECT_EQ(r.status, 0) << r.err;
      return read_particle_checkpoint(file(name)).particles;
    };
    const Particles dense = particles("rbf", "rbf.h5");
    const Particles local = particles("rbf-local", "local.h5");
    std::vector<double> d(dense.count());
    for (std::size_t p = 0; p < dense.count(); ++p) {
      d[p] = (dense.stress[p] - local.stress[p]).cwiseAbs().maxCoeff() / rho_g_h0;
    }
    if (d.empty()) return Difference{};
    std::sort(d.begin(), d.end());
    Difference result;
    result.max = d[d.size() - 1];
    result.p99 = d[d.size() * 99 / 100];
    result.above = static_cast<std::size_t>(
        std::count_if(d.begin(), d.end(), [](double v) { return v > 0.01; }));
    std::cout << "column-short t = " << time << " s, " << dense.count()
              << " particles: |σ_rbf − σ_rbf-local| / ρgH0 max " << result.max
              << ", 99th percentile " << result.p99 << ", " << result.above
              << " particles above 1 %\n";
    return result;
  };
  // Before the mesh entangles the two agree within 1 % of ρgH0 at every particle.
  EXPECT_LT(compare("1.000", "").max, 0.01);
  // At t = 2 s the toe has folded onto the base: 23 inverted elements and 14 more squashed
  // below a fifth of their volume, whose Gauss points (a few cm apart, stresses differing
  // by up to 0.6 ρgH0) are no RBF centres by default. The rest of the toe still varies by
  // ~20 % of ρgH0 from element to element, so the two interpolants differ there between
  // the Gauss points (measured: 1225 of 32 000 particles above 1 %, all at x > 39 m and
  // y < 6 m; 99th percentile 3.0 %, max 20 %; with every Gauss point a centre: 6255
  // particles, max 117 %). Bounds with room for round-off of the dense LU:
  const Difference toe = compare("2.000", "--allow-inverted");
  EXPECT_LT(toe.p99, 0.05);
  EXPECT_LT(toe.max, 0.3);
  EXPECT_LT(toe.above, 32000U / 20);

  // No particle stress leaves the range of the Gauss stresses by more than the limiter's
  // half-range margin (without the limiter: |σ| up to 2e8 Pa against 7e5 Pa, and MPM blew
  // up within 26 steps).
  const FemCheckpoint fem = read_fem_checkpoint(file("fem") / "fem_t2.000.h5");
  for (const char* name : {"rbf.h5", "local.h5"}) {
    const Particles particles = read_particle_checkpoint(file(name)).particles;
    for (int c = 0; c < 4; ++c) {
      double lo = std::numeric_limits<double>::infinity(), hi = -lo;
      for (const Vec4& s : fem.stress) lo = std::min(lo, s[c]), hi = std::max(hi, s[c]);
      const double margin = 0.5 * (hi - lo) + 1e-9 * std::max(std::abs(lo), std::abs(hi));
      const auto outside =
          std::count_if(particles.stress.begin(), particles.stress.end(),
                        [&](const Vec4& s) { return s[c] < lo - margin || s[c] > hi + margin; });
      EXPECT_EQ(outside, 0) << name << ", stress component " << c;
    }
  }

  // That difference is the data's, not the methods': the same crushed Gauss cloud of
  // t = 2 s carrying a field the mesh resolves (varying on metres, of magnitude ρgH0,
  // σzz and σxy included) gives two interpolants that agree within 1 % of ρgH0 at every
  // particle, and each is within 1 % of the exact field. The FE stress there jumps by up
  // to 0.47 ρgH0 between Gauss points less than 0.5 m apart (a gradient 58 times the
  // lithostatic one): no interpolant through those values can pin down what lies between.
  {
    FemCheckpoint smooth = read_fem_checkpoint(file("fem") / "fem_t2.000.h5");
    const auto field = [rho_g_h0](const Vec2& x) {
      const double syy = -rho_g_h0 * (40.0 - x.y()) / 40.0 * (1.0 + 0.1 * std::sin(x.x() / 8.0));
      const double sxx = 0.3 * syy + 0.05 * rho_g_h0 * std::cos(x.y() / 6.0);
      const double sxy = 0.05 * rho_g_h0 * std::sin(x.x() / 12.0) * std::exp(-x.y() / 20.0);
      return Vec4(sxx, syy, 0.5 * (sxx + syy), sxy);
    };
    for (std::size_t g = 0; g < smooth.stress.size(); ++g) {
      smooth.stress[g] = field(smooth.gauss_coordinates[g]);
    }
    write_checkpoint(file("fem") / "fem_t2.000-smooth.h5", smooth);
    const Difference resolved = compare("2.000-smooth", "--allow-inverted");
    EXPECT_LT(resolved.max, 0.01);
    for (const char* name : {"rbf.h5", "local.h5"}) {
      const Particles particles = read_particle_checkpoint(file(name)).particles;
      double worst = 0.0;
      for (std::size_t p = 0; p < particles.count(); ++p) {
        const Vec4 error = particles.stress[p] - field(particles.coordinates[p]);
        worst = std::max(worst, error.cwiseAbs().maxCoeff() / rho_g_h0);
      }
      std::cout << name << ": resolved field reproduced within " << worst << " ρgH0\n";
      EXPECT_LT(worst, 0.01) << name;
    }
  }
}

}  // namespace
}  // namespace slide
