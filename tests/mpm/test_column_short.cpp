// Regression test of the main case (every case is also a short regression test): column-short pure
// MPM (cases/column-short/case.toml: 32,000 particles, uGIMP, MUSL, APIC, cell volumetric
// smoothing, Mohr–Coulomb on a frictional base) to rest at 20 s on 2 threads. The toe position and
// KE/PE0 at 1, 2 and 3 s (the first half of the collapse) are compared with stored numbers; the
// particle set and its masses must come through exactly; and the deposit's stresses must be
// lithostatic (docs/method.md §6).
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "common/io/checkpoint.hpp"

namespace slide::mpm {
namespace {

namespace fs = std::filesystem;

struct HistoryRow {
  double time, ke_over_pe0, x_toe, runout_normalised;
};

std::vector<HistoryRow> read_history(const fs::path& path) {
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);  // header
  std::vector<HistoryRow> rows;
  while (std::getline(in, line)) {
    std::vector<double> cells;
    std::istringstream s(line);
    for (std::string cell; std::getline(s, cell, ',');) cells.push_back(std::stod(cell));
    rows.push_back({cells.at(0), cells.at(3), cells.at(4), cells.at(6)});
  }
  return rows;
}

// Reference numbers of this run (mpm-solve at commit time; bit-identical on 1 and 2
// threads and across restarts). Tolerance 1e-4 relative: rounding-level changes (a build
// that contracts products into FMAs differently) moved them by less than 1e-9 at 2 s,
// while a change of the physics moves them far more: linear shape functions instead of
// uGIMP shift x_toe by −0.064 m at 1 s and +0.52 m at 3 s, KE/PE0 by +1.1 % at 1 s.
struct Reference {
  double time, x_toe, ke_over_pe0;
};
constexpr Reference references[] = {
    // Re-measured for the case's APIC transfer and cell volumetric smoothing (before: 1 %
    // PIC, no smoothing): x_toe +0.46 %, +0.35 %, +0.25 % and KE/PE0 +2.3 %, +2.8 %,
    // +5.8 % at 1, 2, 3 s (the PIC share no longer takes its energy); then for the Courant
    // step at the particles' current density (the collapse dilates the toe: steps up to
    // 1.1 times shorter): x_toe −0.02 %, −0.02 %, −0.005 %, KE/PE0 +0.02 %, −0.05 %, −0.1 %;
    // then for APIC carrying C_p instead of B_p (the same C_p to round-off): < 1e-6.
    {1.0, 55.3284121, 0.033818606},
    {2.0, 68.8092828, 0.080434168},
    {3.0, 86.7276793, 0.087539664},
};
constexpr double tolerance = 1e-4;

/// The `key=value` fields of the line of `text` that starts with `prefix`.
std::map<std::string, double> fields_of_line(const std::string& text, const std::string& prefix) {
  std::map<std::string, double> fields;
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);) {
    if (line.rfind(prefix, 0) != 0) continue;
    std::istringstream words(line.substr(prefix.size()));
    for (std::string word; words >> word;) {
      const auto equals = word.find('=');
      if (equals != std::string::npos)
        fields[word.substr(0, equals)] = std::stod(word.substr(equals + 1));
    }
  }
  return fields;
}

TEST(ColumnShortPureMpm, CollapseMatchesTheReferenceAndTheDepositIsLithostatic) {
  const fs::path folder = fs::path(SLIDE_BINARY_DIR) / "tests" / "mpm" / "cli" / "column_short";
  fs::remove_all(folder);
  fs::create_directories(folder);
  const fs::path program = fs::path(SLIDE_BINARY_DIR) / "bin" / "mpm-solve";
  const fs::path case_file = fs::path(SLIDE_SOURCE_DIR) / "cases" / "column-short" / "case.toml";
  const std::string command =
      fmt::format("{} {} -o {} --threads 2 --no-vtk --quiet > {} 2>&1", program.string(),
                  case_file.string(), folder.string(), (folder / "log.txt").string());
  ASSERT_EQ(std::system(command.c_str()), 0) << command;

  const std::vector<HistoryRow> history = read_history(folder / "mpm_history.csv");
  for (const Reference& r : references) {
    const auto row = std::find_if(history.begin(), history.end(), [&](const HistoryRow& h) {
      return std::abs(h.time - r.time) < 1e-9;
    });
    ASSERT_NE(row, history.end()) << "no history row at t = " << r.time;
    std::printf(
        "column-short pure MPM t = %.0f s: x_toe %.7f m (reference %.7f), R_N %.6f, "
        "KE/PE0 %.9f (reference %.9f)\n",
        r.time, row->x_toe, r.x_toe, row->runout_normalised, row->ke_over_pe0, r.ke_over_pe0);
    EXPECT_NEAR(row->x_toe / r.x_toe, 1.0, tolerance) << "t = " << r.time;
    EXPECT_NEAR(row->ke_over_pe0 / r.ke_over_pe0, 1.0, tolerance) << "t = " << r.time;
    EXPECT_NEAR(row->runout_normalised, (row->x_toe - 50.0) / 50.0, 1e-12);
  }

  // The particle set: 50 × 40 cells of 4 × 4 particles, none lost or frozen, every mass
  // unchanged to the bit; the total is ρ L0 H0, and PE0 = ρ g L0 H0²/2.
  const ParticleCheckpoint start = read_particle_checkpoint(folder / "mpm_t0.000.h5");
  const ParticleCheckpoint end = read_particle_checkpoint(folder / "mpm_final.h5");
  ASSERT_EQ(start.particles.count(), 32000u);
  ASSERT_EQ(end.particles.count(), 32000u);
  EXPECT_EQ(end.header.time, 20.0);
  EXPECT_EQ(std::get<std::int64_t>(end.solver.at("frozen_particles")), 0);
  std::vector<double> mass_by_id(start.particles.count(), -1.0);
  for (std::size_t k = 0; k < start.particles.count(); ++k)
    mass_by_id.at(static_cast<std::size_t>(start.particles.id[k])) = start.particles.mass[k];
  double total = 0.0;
  for (std::size_t k = 0; k < end.particles.count(); ++k) {
    ASSERT_EQ(end.particles.mass[k], mass_by_id.at(static_cast<std::size_t>(end.particles.id[k])))
        << "particle " << k;
    total += end.particles.mass[k];
  }
  const double density = 1700.0, g = 9.81, length = 50.0, height = 40.0;
  EXPECT_NEAR(total / (density * length * height), 1.0, 1e-12);
  EXPECT_NEAR(end.header.pe0 / (0.5 * density * g * length * height * height), 1.0, 1e-12);

  // The deposit at rest: e_p = |σyy − σyy,lith| / (ρ g H0) (slide-metrics measure). Without
  // volumetric smoothing (APIC alone) the 99th percentile is 1.71 and the maximum 4.83,
  // with a thousand particles near the base several times their overburden; with the 1 %
  // PIC blend 1.47 and 4.01 (mpm/README.md's table). With it: 0.106 and 0.206. Targets
  // (issue 11): 99th percentile ≤ 0.25, maximum ≤ 0.6.
  const fs::path metrics_program = fs::path(SLIDE_BINARY_DIR) / "bin" / "slide-metrics";
  const fs::path report = folder / "measure.txt";
  const std::string measure =
      fmt::format("{} measure {} {} > {} 2>&1", metrics_program.string(), case_file.string(),
                  (folder / "mpm_final.h5").string(), report.string());
  ASSERT_EQ(std::system(measure.c_str()), 0) << measure;
  std::ifstream in(report);
  std::string text;
  for (std::string line; std::getline(in, line);) text += line + "\n";
  std::printf("%s", text.c_str());
  const auto quality = fields_of_line(text, "stress_quality:");
  ASSERT_TRUE(quality.contains("p99") && quality.contains("max")) << text;
  EXPECT_GT(quality.at("deposit"), 5000.0) << "a deposit at rest to measure";
  EXPECT_LE(quality.at("p99"), 0.25);
  EXPECT_LE(quality.at("max"), 0.6);
  ASSERT_TRUE(text.find("strays=0") != std::string::npos) << text;
}

}  // namespace
}  // namespace slide::mpm
