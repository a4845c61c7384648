// The sweep layer of slide-metrics (tools/sweep_metrics.*): FE histories, the valid
// transfer times of docs/method.md §7 and the sweep table of docs/contract.md, on hand-made data.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "common/base/error.hpp"
#include "common/io/checkpoint.hpp"
#include "tools/sweep_metrics.hpp"

namespace slide::tools {
namespace {

namespace fs = std::filesystem;

const char* const contract_header =
    "time,kinetic_energy,pe0,ke_over_pe0,jacobian_ratio_min,jacobian_ratio_avg,eps_q_avg,"
    "eps_q_max,n_elements_yielding";

fs::path write_file(const std::string& name, const std::string& text) {
  const fs::path dir = fs::path(SLIDE_BINARY_DIR) / "tests" / "tools" / "data";
  fs::create_directories(dir);
  std::ofstream(dir / name) << text;
  return dir / name;
}

Case column_short() {
  return load_case(fs::path(SLIDE_SOURCE_DIR) / "cases/column-short/case.toml");
}

/// A history with one row per second and the given (|J_t|/|J_0|)_min.
std::vector<FemHistoryRow> history(const std::vector<double>& jacobian_min) {
  std::vector<FemHistoryRow> rows;
  for (std::size_t i = 0; i < jacobian_min.size(); ++i) {
    FemHistoryRow row;
    row.time = static_cast<double>(i);
    row.jacobian_ratio_min = jacobian_min[i];
    rows.push_back(row);
  }
  return rows;
}

TEST(FemHistory, ColumnsAreReadByNameAndNanMeansUndefined) {
  // Columns in another order than the writer's: the reader must go by name.
  const fs::path path = write_file(
      "reordered.csv",
      "eps_q_max,time,kinetic_energy,pe0,ke_over_pe0,jacobian_ratio_min,jacobian_ratio_avg,"
      "eps_q_avg,n_elements_yielding\n"
      "0,0,0,100,0,1,nan,nan,0\n"
      "0.7, 1.5 ,2.5,100,0.025,0.86,0.99,0.126,42\n");
  const auto rows = read_fem_history(path);
  ASSERT_EQ(rows.size(), 2U);
  EXPECT_TRUE(std::isnan(rows[0].jacobian_ratio_avg));
  EXPECT_DOUBLE_EQ(rows[1].time, 1.5);
  EXPECT_DOUBLE_EQ(rows[1].eps_q_max, 0.7);
  EXPECT_DOUBLE_EQ(rows[1].jacobian_ratio_min, 0.86);
  EXPECT_DOUBLE_EQ(rows[1].n_elements_yielding, 42.0);
  ASSERT_TRUE(history_at(rows, 1.5 + 1e-9).has_value());
  EXPECT_DOUBLE_EQ(history_at(rows, 1.5)->ke_over_pe0, 0.025);
  EXPECT_FALSE(history_at(rows, 1.4).has_value());
}

TEST(FemHistory, AreaAndShapeColumnsAreReadWhenPresentAndNanWhenNot) {
  // The writer's full header (fem/fem_output.hpp): area_ratio and the scaled Jacobian after
  // n_elements_yielding.
  const fs::path path =
      write_file("with-shape.csv", std::string(contract_header) +
                                       ",area_ratio,scaled_jacobian_min,scaled_jacobian_avg\n"
                                       "0,0,100,0,1,nan,nan,0,0,1,1,nan\n"
                                       "1,2,100,0.02,0.9,0.98,0.05,0.3,7,0.97,0.42,0.81\n");
  const auto rows = read_fem_history(path);
  ASSERT_EQ(rows.size(), 2U);
  EXPECT_DOUBLE_EQ(rows[0].area_ratio, 1.0);
  EXPECT_TRUE(std::isnan(rows[0].scaled_jacobian_avg));
  EXPECT_DOUBLE_EQ(rows[1].n_elements_yielding, 7.0);
  EXPECT_DOUBLE_EQ(rows[1].area_ratio, 0.97);
  EXPECT_DOUBLE_EQ(rows[1].scaled_jacobian_min, 0.42);
  EXPECT_DOUBLE_EQ(rows[1].scaled_jacobian_avg, 0.81);
  // A history written before those columns: the same rows, the new fields NaN.
  const auto old = read_fem_history(write_file(
      "without-shape.csv", std::string(contract_header) + "\n0,0,100,0,1,nan,nan,0,0\n"));
  ASSERT_EQ(old.size(), 1U);
  EXPECT_TRUE(std::isnan(old[0].area_ratio));
  EXPECT_TRUE(std::isnan(old[0].scaled_jacobian_min));
  EXPECT_TRUE(std::isnan(old[0].scaled_jacobian_avg));
}

void expect_error(const fs::path& path, const std::string& part) {
  try {
    read_fem_history(path);
    ADD_FAILURE() << path << " was accepted";
  } catch (const Error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(path.string()), std::string::npos) << message;
    EXPECT_NE(message.find(part), std::string::npos) << message;
  }
}

TEST(FemHistory, BrokenFilesAreErrorsNamingFileLineAndProblem) {
  expect_error(write_file("missing-column.csv", "time,kinetic_energy\n0,0\n"),
               "missing column pe0");
  expect_error(write_file("not-a-number.csv",
                          std::string(contract_header) + "\n0,0,1,0,1,,,0,0\n1,0,1,x,1,1,0,0,0\n"),
               ":3: \"x\" is not a number");
  expect_error(write_file("short-row.csv", std::string(contract_header) + "\n0,0,1\n"),
               ":2: 3 cells, expected 9");
  expect_error(write_file("empty.csv", ""), "empty file");
  expect_error(fs::path(SLIDE_BINARY_DIR) / "no-such-history.csv", "cannot open");
}

TEST(FemHistory, WriterOrderCrlfAndBlankLinesAndTheTimeTolerance) {
  // The docs/contract.md header in the writer's order, Windows line ends (the trailing \r of
  // every cell is trimmed) and a blank line between rows and at the end (skipped).
  const fs::path path = write_file("contract-order.csv", std::string(contract_header) +
                                                             "\r\n"
                                                             "0,0,3.4e9,0,1,nan,nan,0,0\r\n"
                                                             "\n"
                                                             "0.1,1.7e7,3.4e9,0.005,0.98,0.99,"
                                                             "0.04,0.06,12\r\n"
                                                             "\n");
  const auto rows = read_fem_history(path);
  ASSERT_EQ(rows.size(), 2U);
  EXPECT_DOUBLE_EQ(rows[0].pe0, 3.4e9);
  EXPECT_TRUE(std::isnan(rows[0].eps_q_avg));
  EXPECT_DOUBLE_EQ(rows[1].time, 0.1);
  EXPECT_DOUBLE_EQ(rows[1].kinetic_energy, 1.7e7);
  EXPECT_DOUBLE_EQ(rows[1].ke_over_pe0, 0.005);  // 1.7e7 / 3.4e9
  EXPECT_DOUBLE_EQ(rows[1].jacobian_ratio_avg, 0.99);
  EXPECT_DOUBLE_EQ(rows[1].eps_q_avg, 0.04);
  EXPECT_DOUBLE_EQ(rows[1].n_elements_yielding, 12.0);  // the last cell, "12\r" trimmed

  // history_at: |t_row − t| < 1e-6 s. 0.1 + 0.9 µs matches the second row, 0.1 + 2 µs
  // and 0.1 − 2 µs match none; t = 0 picks the first row, not the second.
  ASSERT_TRUE(history_at(rows, 0.1 + 0.9e-6).has_value());
  EXPECT_DOUBLE_EQ(history_at(rows, 0.1 + 0.9e-6)->jacobian_ratio_min, 0.98);
  EXPECT_FALSE(history_at(rows, 0.1 + 2e-6).has_value());
  EXPECT_FALSE(history_at(rows, 0.1 - 2e-6).has_value());
  ASSERT_TRUE(history_at(rows, 0.0).has_value());
  EXPECT_DOUBLE_EQ(history_at(rows, 0.0)->jacobian_ratio_min, 1.0);
  EXPECT_FALSE(history_at({}, 0.0).has_value());
}

TEST(TransferTimes, SweepStopsAtTheFirstEntangledMesh) {
  // column-short sweeps t_T = 0, 1, ..., 8 s; the mesh inverts between 2 and 3 s and
  // untangles again later, which must not bring later times back.
  const Case c = column_short();
  EXPECT_EQ(valid_transfer_times(c, history({1.0, 0.9, 0.4, -0.1, 0.2, 0.3})),
            (std::vector<double>{0.0, 1.0, 2.0}));
  // (|J_t|/|J_0|)_min = 0 exactly is entangled (docs/method.md §7 asks for > 0).
  EXPECT_EQ(valid_transfer_times(c, history({1.0, 0.0})), (std::vector<double>{0.0}));
  // An element inverted at a corner while every centre Jacobian is still positive
  // (scaled_jacobian_min < 0): fem2mpm would refuse it, so the sweep stops there too.
  auto rows = history({1.0, 0.9, 0.8, 0.7});
  for (auto& row : rows) row.scaled_jacobian_min = 0.5;
  rows[2].scaled_jacobian_min = -0.1;
  EXPECT_EQ(valid_transfer_times(c, rows), (std::vector<double>{0.0, 1.0}));
  rows[2].scaled_jacobian_min = 0.0;  // a flat corner is degenerate, not inverted
  EXPECT_EQ(valid_transfer_times(c, rows), (std::vector<double>{0.0, 1.0, 2.0, 3.0}));
}

TEST(TransferTimes, SweepStopsAtTheFemEndAndWhereTheHistoryEnds) {
  Case c = column_short();
  const std::vector<double> intact(10, 1.0);                       // rows at 0, 1, ..., 9 s
  EXPECT_EQ(valid_transfer_times(c, history(intact)).size(), 9U);  // 0 … 8 s (FE end 8 s)
  c.fem.end_time = 3.5;
  EXPECT_EQ(valid_transfer_times(c, history(intact)), (std::vector<double>{0, 1, 2, 3}));
  c.fem.end_time = 8.0;
  EXPECT_EQ(valid_transfer_times(c, history({1.0, 1.0})), (std::vector<double>{0, 1}));
}

TEST(CaseNumbers, CriticalTimeAndParticleSpacing) {
  const Case c = column_short();
  EXPECT_NEAR(critical_time(c), std::sqrt(40.0 / 9.81), 1e-12);  // 2.01928 s
  EXPECT_DOUBLE_EQ(particle_spacing(c), 0.25);                   // 1 m cells, 4 × 4
}

RunMetrics run(const std::string& name, std::optional<double> tt, std::vector<double> heights,
               double x_toe, double initial_length) {
  RunMetrics r;
  r.run = name;
  r.tt = tt;
  r.profile.bin_width = 2.0;
  r.profile.height = std::move(heights);
  r.profile.x_toe = x_toe;
  r.measures = runout_measures(r.profile, initial_length);
  return r;
}

/// The cells of a Markdown table row: split at every "|" not escaped as "\\|".
std::vector<std::string> markdown_cells(const std::string& row) {
  std::vector<std::string> cells;
  std::string current;
  for (std::size_t i = 0; i < row.size(); ++i) {
    if (row[i] == '\\' && i + 1 < row.size() && row[i + 1] == '|') {
      current += "\\|";
      ++i;
    } else if (row[i] == '|') {
      cells.push_back(current);
      current.clear();
    } else {
      current += row[i];
    }
  }
  cells.push_back(current);
  // "| a | b |" splits into "", " a ", " b ", "": drop the outer empties.
  if (!cells.empty() && cells.front().empty()) cells.erase(cells.begin());
  if (!cells.empty() && cells.back().empty()) cells.pop_back();
  return cells;
}

/// GitHub renders a table only if the header has as many cells as the delimiter row;
/// every body row must have that many too.
void expect_well_formed_markdown_table(const std::string& md) {
  std::istringstream lines(md);
  std::string header, delimiter;
  ASSERT_TRUE(std::getline(lines, header));
  ASSERT_TRUE(std::getline(lines, delimiter));
  const std::size_t columns = markdown_cells(delimiter).size();
  EXPECT_EQ(markdown_cells(header).size(), columns) << header;
  for (const auto& cell : markdown_cells(delimiter)) EXPECT_EQ(cell, "---");
  for (std::string row; std::getline(lines, row);) {
    EXPECT_EQ(markdown_cells(row).size(), columns) << row;
  }
}

TEST(SweepTable, ErrorsAndRmseAgainstTheReferenceRun) {
  // L0 = 5 m so that four 2 m bins reach past it. Reference tt0: heights 10, 8, 6, 4 m,
  // toe 7.5 m: R = 2.5 m, R_N = 0.5, H_c = 10 m.
  // tt1: heights 9, 8, 6, 5, toe 7.75: R_N = 0.55 (error +0.1), H_c = 9 (error −0.1),
  //   RMSE over the reference's 4 bins with p = 0.25 m:
  //   sqrt(((9−10)/10.25)² + ((5−4)/4.25)²)/4) = 0.127359.
  // pure-mpm: heights 10, 8, 6, toe 5.5: R_N = 0.1 (error −0.8), H_c error 0, the missing
  //   fourth bin counts as height 0: sqrt(((0−4)/4.25)²/4) = 0.470588.
  Case c = column_short();
  c.metrics.initial_length = 5.0;
  std::vector<RunMetrics> runs{run("tt0", 0.0, {10, 8, 6, 4}, 7.5, 5.0),
                               run("tt1", 1.0, {9, 8, 6, 5}, 7.75, 5.0),
                               run("pure-mpm", std::nullopt, {10, 8, 6}, 5.5, 5.0)};
  FemHistoryRow at0, at1;
  at0.jacobian_ratio_min = 1.0;
  at0.jacobian_ratio_avg = at0.eps_q_avg = std::nan("");  // no element above 3 % yet
  at1.jacobian_ratio_min = 0.86;
  at1.jacobian_ratio_avg = 0.99;
  at1.eps_q_avg = 0.126;
  runs[0].fem_at_transfer = at0;
  runs[1].fem_at_transfer = at1;

  EXPECT_EQ(sweep_csv(c, runs, "tt0"),
            "run,tt,tt_over_tauc,runout,runout_normalised,runout_normalised_error,crest_height,"
            "crest_height_error,rmse,jacobian_ratio_min,jacobian_ratio_avg,eps_q_avg,"
            "ke_over_pe0_peak,ke_over_pe0_peak_time,ke_over_pe0_peak_time_over_tauc,"
            "stress_quality_p50,stress_quality_p90,stress_quality_p99,stress_quality_max,"
            "x_toe,x_front_95,sheet_length,sheet_mass_share,sheet_thickness\n"
            "tt0,0,0,2.5,0.5,0,10,0,0,1,,,,,,,,,,7.5,0,0,0,0\n"
            "tt1,1,0.495227,2.75,0.55,0.1,9,-0.1,0.127359,0.86,0.99,0.126,,,,,,,,7.75,0,0,0,0\n"
            "pure-mpm,,,0.5,0.1,-0.8,10,0,0.470588,,,,,,,,,,,5.5,0,0,0,0\n");

  // Without the reference run the errors and RMSE are not defined: empty cells. (No
  // energy history and no particles measured here: the KE/PE0 and stress-quality cells
  // are empty too.)
  const std::string without = sweep_csv(c, runs, "tt9");
  EXPECT_NE(without.find("tt1,1,0.495227,2.75,0.55,,9,,,0.86,0.99,0.126,,,,,,,,7.75,0,0,0,0\n"),
            std::string::npos)
      << without;

  const std::string md = sweep_markdown(c, runs, "tt0");
  EXPECT_NE(md.find("| tt1 |"), std::string::npos) << md;
  EXPECT_NE(md.find("+10.0 %"), std::string::npos) << md;  // R_N error of tt1
  EXPECT_NE(md.find("-80.0 %"), std::string::npos) << md;  // R_N error of pure-mpm
  // The header's |J_t|/|J_0| is escaped: 22 header cells like the 22 delimiter cells.
  EXPECT_NE(md.find("(\\|J_t\\|/\\|J_0\\|)_min"), std::string::npos) << md;
  EXPECT_EQ(markdown_cells(md.substr(0, md.find('\n'))).size(), 22U);
  expect_well_formed_markdown_table(md);
}

TEST(SweepTable, NoRelativeErrorOfARunoutUnderOneBin) {
  // A reference toe advance of 0.1 m on 2 m bins (L0 = 5 m, toe 5.1 m): a run 0.2 m
  // behind it would be "−200 %". The R_N error stays empty, the crest's is given.
  Case c = column_short();
  c.metrics.initial_length = 5.0;
  ASSERT_EQ(c.metrics.bin_width, 2.0);
  std::vector<RunMetrics> runs{run("tt0", 0.0, {10, 8, 6}, 5.1, 5.0),
                               run("tt1", 1.0, {9, 8, 6}, 4.9, 5.0)};
  const std::string csv = sweep_csv(c, runs, "tt0");
  const auto row = csv.substr(csv.find("\ntt1,") + 1);
  // run, tt, tt_over_tauc, runout, runout_normalised, runout_normalised_error, crest, error
  EXPECT_EQ(row.substr(0, row.find(",9,")), "tt1,1,0.495227,-0.1,-0.02,");
  EXPECT_NE(row.find(",9,-0.1,"), std::string::npos);  // H_c 9 against 10
}

TEST(SweepTable, NoNegativeZero) {
  // A run identical to the reference gives (x − x)/x_ref = −0 where x_ref < 0, and values
  // that round to zero print as "-0.0": both are written without the minus sign. The
  // reference's R_N of −0.004 (a geostatic column, R = −0.02 m, under one bin) has no
  // relative error at all; the crest's error of −1e-7 would print as "-0.0 %".
  Case c = column_short();
  c.metrics.initial_length = 5.0;
  std::vector<RunMetrics> runs{run("tt0", 0.0, {4.0, 4.0}, 4.98, 5.0),
                               run("pure-mpm", std::nullopt, {4.0, 4.0}, 4.98, 5.0)};
  runs[1].measures.crest_height = 4.0 * (1.0 - 1e-7);  // error −1e-7: "-0.0 %"
  const std::string csv = sweep_csv(c, runs, "tt0");
  EXPECT_NE(csv.find("tt0,0,0,-0.02,-0.004,,4,0,0,"), std::string::npos) << csv;
  EXPECT_EQ(csv.find(",-0,"), std::string::npos) << csv;
  const std::string md = sweep_markdown(c, runs, "tt0");
  EXPECT_EQ(md.find("-0.0 %"), std::string::npos) << md;
  EXPECT_NE(md.find("| pure-mpm |  |  | -0.02 | -0.004 |  | 4.00 | +0.0 % |"), std::string::npos)
      << md;
}

TEST(EnergyHistory, PeaksOfFemAndMpmHistoriesAndTheirErrors) {
  // An MPM history in the writer's order and an FE history (the docs/contract.md columns): the time
  // and ke_over_pe0 columns are found by name; nan samples do not count.
  const auto mpm = read_energy_history(
      write_file("energy-mpm.csv",
                 "time,kinetic_energy,pe0,ke_over_pe0,x_toe,runout,runout_normalised\n"
                 "2,1,10,0.1,60,10,0.2\n2.1,3,10,0.3,61,11,0.22\n2.2,nan,10,nan,62,12,0.24\n"
                 "2.3,2,10,0.2,63,13,0.26\n"));
  ASSERT_EQ(mpm.size(), 4U);
  EXPECT_DOUBLE_EQ(mpm[1].time, 2.1);
  EXPECT_DOUBLE_EQ(mpm[1].ke_over_pe0, 0.3);
  ASSERT_TRUE(ke_over_pe0_peak(mpm).has_value());
  EXPECT_DOUBLE_EQ(ke_over_pe0_peak(mpm)->ke_over_pe0, 0.3);
  EXPECT_DOUBLE_EQ(ke_over_pe0_peak(mpm)->time, 2.1);
  EXPECT_FALSE(ke_over_pe0_peak({}).has_value());
  EXPECT_FALSE(ke_over_pe0_peak({{0.0, std::nan("")}}).has_value());

  // A transfer at 2 s: FE rows at 0, 1, 2 s count (the FE peak 0.5 at 2 s wins), the FE
  // row at 3 s does not.
  std::vector<FemHistoryRow> fem = history({1.0, 1.0, 1.0, 1.0});
  fem[1].ke_over_pe0 = 0.05;
  fem[2].ke_over_pe0 = 0.5;
  fem[3].ke_over_pe0 = 0.9;
  const auto samples = transfer_run_energy(fem, 2.0, mpm);
  ASSERT_EQ(samples.size(), 7U);  // 3 FE rows + 4 MPM rows
  EXPECT_DOUBLE_EQ(ke_over_pe0_peak(samples)->ke_over_pe0, 0.5);
  EXPECT_DOUBLE_EQ(ke_over_pe0_peak(samples)->time, 2.0);
  // A transfer at 1 s: the MPM peak 0.3 at 2.1 s.
  EXPECT_DOUBLE_EQ(ke_over_pe0_peak(transfer_run_energy(fem, 1.0, mpm))->time, 2.1);

  // The FE history format reads too (pure-fem's peak).
  const auto fe = read_energy_history(
      write_file("energy-fem.csv",
                 std::string(contract_header) +
                     "\n0,0,3.4e9,0,1,nan,nan,0,0\n2.4,4.8e8,3.4e9,0.142,0.5,0.9,0.3,1,9\n"));
  EXPECT_DOUBLE_EQ(ke_over_pe0_peak(fe)->time, 2.4);

  // Broken files: errors naming the file, the line and the problem.
  for (const auto& [name, text, part] :
       {std::tuple<std::string, std::string, std::string>{"energy-no-ke.csv", "time,x_toe\n0,1\n",
                                                          "missing column ke_over_pe0"},
        {"energy-bad.csv", "time,ke_over_pe0\n0,0\n1,fast\n", ":3: \"fast\" is not a number"},
        {"energy-short.csv", "time,ke_over_pe0,x_toe\n0,0\n", ":2: 2 cells, expected 3"}}) {
    const fs::path path = write_file(name, text);
    try {
      read_energy_history(path);
      ADD_FAILURE() << name << " was accepted";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
    }
  }
}

/// The fields of a final state besides the positions: σyy and velocity of every particle
/// (empty: 0 and at rest) and the density of the file's material 0.
struct ParticleFields {
  std::vector<double> sigma_yy;
  std::vector<Vec2> velocity;
  double density = 1700.0;
};

/// A final particle state written as a checkpoint, as mpm-solve ("mpm") or the pure-FE
/// run ("particles") would leave it.
fs::path write_particles(const Case& c, const std::string& name, CheckpointKind kind,
                         const std::vector<Vec2>& points, const ParticleFields& fields = {}) {
  ParticleCheckpoint checkpoint;
  checkpoint.header.kind = kind;
  checkpoint.header.producer = "tests_tools";
  checkpoint.header.time = 20.0;
  checkpoint.header.case_name = c.name;
  checkpoint.header.pe0 = 3.4e9;
  checkpoint.materials = c.materials;
  checkpoint.materials[0].density = fields.density;
  if (kind == CheckpointKind::particles) checkpoint.transfer = {8.0, "4x4", "rbf", "none", 0, 0};
  Particles& p = checkpoint.particles;
  p.resize(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    p.coordinates[i] = points[i];
    // σxx, σzz and σxy far from anything lithostatic: only σyy may be measured.
    const double syy = fields.sigma_yy.empty() ? 0.0 : fields.sigma_yy[i];
    p.stress[i] = Vec4(-1e6, syy, -2e6, 3e5);
    if (!fields.velocity.empty()) p.velocity[i] = fields.velocity[i];
    p.volume[i] = 0.0625;
    p.mass[i] = 1700.0 * 0.0625;
    p.size[i] = Vec2(0.25, 0.25);
    p.material_id[i] = 0;
    p.element[i] = -1;
    p.id[i] = static_cast<std::int64_t>(i);
  }
  const fs::path dir = fs::path(SLIDE_BINARY_DIR) / "tests" / "tools" / "data" / "runs";
  fs::create_directories(dir);
  write_checkpoint(dir / name, checkpoint);
  return dir / name;
}

TEST(SweepTable, MeasuredCheckpointsGiveTheHandComputedTable) {
  // column-short with L0 = 5 m (bins 2 m, 99th percentile, p = 0.25 m, τc = sqrt(40/9.81)
  // = 2.01928 s) and a foundation level of 0.5 m (particles at y ≤ 0.5 m not measured).
  Case c = column_short();
  c.metrics.initial_length = 5.0;
  c.metrics.foundation_level = 0.5;

  // tt0 (reference): bin 0 holds y = 9 and 10 → 99th percentile 9 + 0.99·(10 − 9) = 9.99;
  //   bins 1–3: 8, 6, 4 (toe 7.5 m). (9, 0.25) lies under the foundation level, so bin 4
  //   stays empty and (11, 1) is a stray. R = 7.5 − 5 = 2.5, R_N = 0.5, H_c = 9.99.
  //   Stress quality at rest (H0 = 40 m): every particle has σyy = −0.2 ρ g H0, so
  //   e_p = |−0.2 + (h_b − y)/H0| over the five measured particles (not (9, 0.25) nor the
  //   stray): (h_b − y)/H0 = 0.99/40, −0.01/40, 0, 0, 0 → e = 0.17525, 0.20025, 0.2 ×3;
  //   median 0.2, p90 (rank 3.6) 0.2 + 0.6·0.00025 = 0.20015, p99 (rank 3.96) 0.20024,
  //   max 0.20025.
  const std::vector<Vec2> tt0_points{{0.5, 9.0}, {1.5, 10.0}, {3.0, 8.0}, {5.0, 6.0},
                                     {7.5, 4.0}, {9.0, 0.25}, {11.0, 1.0}};
  const double column_weight = 1700.0 * gravity_acceleration * 40.0;  // ρ g H0, Pa
  const fs::path tt0 =
      write_particles(c, "tt0.h5", CheckpointKind::mpm, tt0_points,
                      {std::vector<double>(tt0_points.size(), -0.2 * column_weight), {}});
  // tt1: heights 9, 8, 6, 5, 2 (toe 8.5): R = 3.5, R_N = 0.7 (error (0.7 − 0.5)/0.5 = 0.4),
  //   H_c = 9 (error (9 − 9.99)/9.99 = −0.0990991). RMSE over the reference's bins 0–3
  //   (toe 7.5 in bin 3), y_ref + p = 10.24, 8.25, 6.25, 4.25:
  //   sqrt((((9 − 9.99)/10.24)² + ((5 − 4)/4.25)²)/4) = sqrt((0.0093470 + 0.0553633)/4)
  //   = 0.127191.
  //   Stress quality: the file's material has ρ = 2000 kg/m³ (used, not the case's 1700);
  //   each bin holds one particle, its own surface (h_b = y), and σyy = −0.1 ρ g H0, so
  //   e = 0.1 at every percentile; the toe particle moves (2 m/s, σyy tensile 0.5 MPa)
  //   and is left out.
  const double tt1_weight = 2000.0 * gravity_acceleration * 40.0;
  const fs::path tt1 = write_particles(
      c, "tt1.h5", CheckpointKind::mpm,
      {{1.0, 9.0}, {3.0, 8.0}, {5.0, 6.0}, {6.5, 5.0}, {8.5, 2.0}},
      {{-0.1 * tt1_weight, -0.1 * tt1_weight, -0.1 * tt1_weight, -0.1 * tt1_weight, 5e5},
       {{0, 0}, {0, 0}, {0.001, -0.002}, {0, 0}, {2.0, 0.0}},
       2000.0});
  // pure-fem: bin 0 holds 11 and 12 → 11.99, bin 1: 7 (toe 2.5), bin 2 empty so (6, 3) is
  //   a stray. R = −2.5, R_N = −0.5 (error −2), H_c = 11.99 (error 2/9.99 = 0.2002).
  //   RMSE: bins 2 and 3 count as height 0: errors 2/10.24 = 0.1953125, −1/8.25 =
  //   −0.121212, −6/6.25 = −0.96, −4/4.25 = −0.941176; squares sum to 1.8602525;
  //   sqrt(1.8602525/4) = 0.681955.
  //   Every particle still moves (≥ 1 cm/s): no deposit, empty stress-quality cells.
  const fs::path pure_fem =
      write_particles(c, "pure-fem.h5", CheckpointKind::particles,
                      {{1.0, 12.0}, {1.2, 11.0}, {2.5, 7.0}, {6.0, 3.0}},
                      {{}, {{0.01, 0.0}, {0.0, -0.01}, {0.5, 0.1}, {0.02, 0.0}}, 1700.0});

  // The FE history: the mesh inverts between 2 and 3 s, so the sweep is 0, 1, 2 s.
  const fs::path history_file =
      write_file("sweep-history.csv", std::string(contract_header) +
                                          "\n"
                                          "0,0,3.4e9,0,1,nan,nan,0,0\n"
                                          "1,1.7e7,3.4e9,0.005,0.9,0.97,0.051,0.4,120\n"
                                          "2,3.4e7,3.4e9,0.01,0.3,0.9,0.12,0.9,400\n"
                                          "3,3.4e7,3.4e9,0.01,-0.2,0.85,0.2,1.5,600\n");
  const auto history = read_fem_history(history_file);
  ASSERT_EQ(valid_transfer_times(c, history), (std::vector<double>{0.0, 1.0, 2.0}));

  std::vector<RunMetrics> runs{measure_run(c, "tt0", 0.0, tt0), measure_run(c, "tt1", 1.0, tt1),
                               measure_run(c, "pure-fem", std::nullopt, pure_fem)};
  runs[0].fem_at_transfer = history_at(history, 0.0);
  runs[1].fem_at_transfer = history_at(history, 1.0);

  // measure_run itself, on the numbers above.
  EXPECT_EQ(runs[0].run, "tt0");
  EXPECT_EQ(runs[1].tt, std::optional<double>(1.0));
  EXPECT_FALSE(runs[2].tt.has_value());
  EXPECT_FALSE(runs[2].fem_at_transfer.has_value());
  EXPECT_DOUBLE_EQ(runs[0].profile.bin_width, 2.0);
  ASSERT_EQ(runs[0].profile.height.size(), 4U);
  EXPECT_NEAR(runs[0].profile.height[0], 9.99, 1e-12);
  EXPECT_DOUBLE_EQ(runs[0].profile.height[3], 4.0);
  EXPECT_EQ(runs[0].profile.stray_count, 1U);  // (11, 1); (9, 0.25) is not measured
  EXPECT_DOUBLE_EQ(runs[0].measures.x_toe, 7.5);
  EXPECT_DOUBLE_EQ(runs[0].measures.runout, 2.5);
  EXPECT_DOUBLE_EQ(runs[0].measures.runout_normalised, 0.5);
  EXPECT_NEAR(runs[0].measures.crest_height, 9.99, 1e-12);
  EXPECT_EQ(runs[1].profile.height.size(), 5U);
  EXPECT_DOUBLE_EQ(runs[1].measures.runout, 3.5);
  EXPECT_NEAR(runs[1].measures.runout_normalised, 0.7, 1e-12);
  EXPECT_EQ(runs[2].profile.height.size(), 2U);
  EXPECT_EQ(runs[2].profile.stray_count, 1U);
  EXPECT_DOUBLE_EQ(runs[2].measures.runout_normalised, -0.5);
  EXPECT_NEAR(runs[2].measures.crest_height, 11.99, 1e-12);
  EXPECT_EQ(runs[0].stress_quality.deposit_count, 5U);
  EXPECT_NEAR(runs[0].stress_quality.p50, 0.2, 1e-12);
  EXPECT_NEAR(runs[0].stress_quality.p90, 0.20015, 1e-12);
  EXPECT_NEAR(runs[0].stress_quality.p99, 0.20024, 1e-12);
  EXPECT_NEAR(runs[0].stress_quality.max, 0.20025, 1e-12);
  EXPECT_EQ(runs[1].stress_quality.deposit_count, 4U);
  EXPECT_NEAR(runs[1].stress_quality.max, 0.1, 1e-12);
  EXPECT_EQ(runs[2].stress_quality.deposit_count, 0U);
  EXPECT_TRUE(std::isnan(runs[2].stress_quality.p50));
  {
    // The bins and percentile come from the case: with 4 m bins and the median, tt0 has
    // bin 0 = {8, 9, 10} → 9, bin 1 = {4, 6} → 5, bin 2 = {1} (the former stray) → 1;
    // toe 11 m, R = 6 m, R_N = 1.2, no strays.
    Case wide = c;
    wide.metrics.bin_width = 4.0;
    wide.metrics.profile_percentile = 50.0;
    const RunMetrics m = measure_run(wide, "tt0", 0.0, tt0);
    EXPECT_DOUBLE_EQ(m.profile.bin_width, 4.0);
    EXPECT_EQ(m.profile.height, (std::vector<double>{9.0, 5.0, 1.0}));
    EXPECT_EQ(m.profile.stray_count, 0U);
    EXPECT_DOUBLE_EQ(m.measures.runout, 6.0);
    EXPECT_DOUBLE_EQ(m.measures.runout_normalised, 1.2);
  }

  // sweep.csv: the docs/contract.md columns; tt0 has zero errors and RMSE, the NaN averages of
  // the t = 0 history row and everything FE- or tt-related of pure-fem are empty.
  // The KE/PE0 peaks, over the FE phase up to t_T and the run's MPM history:
  // tt0: FE 0 at t = 0, MPM 0, 0.02, 0.02 at 0, 0.5, 1 s → 0.02 at 0.5 s (the earliest of
  //   a tie), t/τc = 0.5/2.01928 = 0.247614.
  // tt1: FE 0, 0.005 at 0, 1 s (the FE rows after 1 s do not count, although 0.01 at 2 s
  //   is larger than the MPM values), MPM 0.004, 0.012, 0.008 at 1, 1.5, 2 s → 0.012 at
  //   1.5 s, t/τc = 0.742841.
  // pure-fem: no history given, empty cells.
  const std::string mpm_header =
      "time,kinetic_energy,pe0,ke_over_pe0,x_toe,runout,runout_normalised\n";
  const auto mpm0 = read_energy_history(write_file(
      "tt0-mpm-history.csv", mpm_header + "0,0,3.4e9,0,5,0,0\n0.5,6.8e7,3.4e9,0.02,6,1,0.2\n"
                                          "1,6.8e7,3.4e9,0.02,7,2,0.4\n"));
  const auto mpm1 = read_energy_history(
      write_file("tt1-mpm-history.csv", mpm_header + "1,1.36e7,3.4e9,0.004,6,1,0.2\n"
                                                     "1.5,4.08e7,3.4e9,0.012,7,2,0.4\n"
                                                     "2,2.72e7,3.4e9,0.008,8,3,0.6\n"));
  runs[0].ke_peak = ke_over_pe0_peak(transfer_run_energy(history, 0.0, mpm0));
  runs[1].ke_peak = ke_over_pe0_peak(transfer_run_energy(history, 1.0, mpm1));
  ASSERT_TRUE(runs[1].ke_peak.has_value());
  EXPECT_DOUBLE_EQ(runs[1].ke_peak->ke_over_pe0, 0.012);
  EXPECT_DOUBLE_EQ(runs[1].ke_peak->time, 1.5);

  // sweep.csv: the docs/contract.md columns, the three KE/PE0 peak columns, then the four
  // stress-quality columns (empty for pure-fem, nothing at rest); tt0 has zero
  // errors and RMSE, the NaN averages of the t = 0 history row and everything FE- or
  // tt-related of pure-fem are empty. tt_over_tauc of tt1 = 1/2.01928 = 0.495227. Then
  // x_toe and the front of 95 % of the mass: equal masses, 5, 5 and 3 measured particles,
  // so 95 % is reached only at the last (x_95 = x_toe, no sheet).
  const std::string csv = sweep_csv(c, runs, "tt0");
  EXPECT_EQ(
      csv,
      "run,tt,tt_over_tauc,runout,runout_normalised,runout_normalised_error,crest_height,"
      "crest_height_error,rmse,jacobian_ratio_min,jacobian_ratio_avg,eps_q_avg,"
      "ke_over_pe0_peak,ke_over_pe0_peak_time,ke_over_pe0_peak_time_over_tauc,"
      "stress_quality_p50,stress_quality_p90,stress_quality_p99,stress_quality_max,"
      "x_toe,x_front_95,sheet_length,sheet_mass_share,sheet_thickness\n"
      "tt0,0,0,2.5,0.5,0,9.99,0,0,1,,,0.02,0.5,0.247614,0.2,0.20015,0.20024,0.20025,7.5,7.5,0,0,0\n"
      "tt1,1,0.495227,3.5,0.7,0.4,9,-0.0990991,0.127191,0.9,0.97,0.051,0.012,1.5,0.742841,"
      "0.1,0.1,0.1,0.1,8.5,8.5,0,0,0\n"
      "pure-fem,,,-2.5,-0.5,-2,11.99,0.2002,0.681955,,,,,,,,,,,2.5,2.5,0,0,0\n");
  // Every row has as many cells as the header (24 columns, 23 commas).
  std::istringstream lines(csv);
  for (std::string line; std::getline(lines, line);) {
    EXPECT_EQ(std::count(line.begin(), line.end(), ','), 23) << line;
  }

  // No reference run (slide-metrics passes "" when there is no tt0): the three error
  // columns and the RMSE are empty in every row, the measures stay.
  EXPECT_EQ(
      sweep_csv(c, runs, ""),
      "run,tt,tt_over_tauc,runout,runout_normalised,runout_normalised_error,crest_height,"
      "crest_height_error,rmse,jacobian_ratio_min,jacobian_ratio_avg,eps_q_avg,"
      "ke_over_pe0_peak,ke_over_pe0_peak_time,ke_over_pe0_peak_time_over_tauc,"
      "stress_quality_p50,stress_quality_p90,stress_quality_p99,stress_quality_max,"
      "x_toe,x_front_95,sheet_length,sheet_mass_share,sheet_thickness\n"
      "tt0,0,0,2.5,0.5,,9.99,,,1,,,0.02,0.5,0.247614,0.2,0.20015,0.20024,0.20025,7.5,7.5,0,0,0\n"
      "tt1,1,0.495227,3.5,0.7,,9,,,0.9,0.97,0.051,0.012,1.5,0.742841,0.1,0.1,0.1,0.1,8.5,8.5,0,0,"
      "0\n"
      "pure-fem,,,-2.5,-0.5,,11.99,,,,,,,,,,,,,2.5,2.5,0,0,0\n");

  // The Markdown table: same numbers, rounded for the report; errors in %, εq,avg in %.
  const std::string md = sweep_markdown(c, runs, "tt0");
  EXPECT_EQ(
      md.substr(md.find('\n') + 1),
      "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n"
      "| tt0 | 0 | 0.00 | 2.50 | 0.500 | +0.0 % | 9.99 | +0.0 % | 0.000 | 1.000 |  |  | "
      "0.02 | 0.50 | 0.25 | 0.200 | 0.200 | 0.200 | 0.200 | 7.50 | 7.50 | 0.00, 0.0 %, 0.00 |\n"
      "| tt1 | 1 | 0.50 | 3.50 | 0.700 | +40.0 % | 9.00 | -9.9 % | 0.127 | 0.900 | 0.970 | "
      "5.1 % | 0.012 | 1.50 | 0.74 | 0.100 | 0.100 | 0.100 | 0.100 | 8.50 | 8.50 | 0.00, 0.0 %, "
      "0.00 |\n"
      "| pure-fem |  |  | -2.50 | -0.500 | -200.0 % | 11.99 | +20.0 % | 0.682 |  |  |  |  "
      "|  |  |  |  |  |  | 2.50 | 2.50 | 0.00, 0.0 %, 0.00 |\n");
  expect_well_formed_markdown_table(md);
}

TEST(SweepTable, MeasuringAMissingParticleFileIsAnErrorNamingIt) {
  const fs::path missing = fs::path(SLIDE_BINARY_DIR) / "tests" / "tools" / "no-such-run.h5";
  try {
    measure_run(column_short(), "tt5", 5.0, missing);
    ADD_FAILURE() << "a missing particle file was measured";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(missing.string()), std::string::npos) << e.what();
  }
}

TEST(SweepTable, ProfilesAreListedPerBinWithTheirCentres) {
  const std::vector<RunMetrics> runs{run("tt0", 0.0, {10, 8.5}, 3.0, 5.0)};
  EXPECT_EQ(profiles_csv(runs), "run,bin,x_centre,height\ntt0,0,1,10\ntt0,1,3,8.5\n");
}

}  // namespace
}  // namespace slide::tools
