// The sweep layer of slide-metrics (tools/sweep_metrics.*): FE histories, the valid
// transfer times of METHOD.md §7 and the sweep table of CONTRACT.md, on hand-made data.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "common/error.hpp"
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

TEST(TransferTimes, SweepStopsAtTheFirstEntangledMesh) {
  // column-short sweeps t_T = 0, 1, ..., 8 s; the mesh inverts between 2 and 3 s and
  // untangles again later, which must not bring later times back.
  const Case c = column_short();
  EXPECT_EQ(valid_transfer_times(c, history({1.0, 0.9, 0.4, -0.1, 0.2, 0.3})),
            (std::vector<double>{0.0, 1.0, 2.0}));
  // (|J_t|/|J_0|)_min = 0 exactly is entangled (METHOD.md §7 asks for > 0).
  EXPECT_EQ(valid_transfer_times(c, history({1.0, 0.0})), (std::vector<double>{0.0}));
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
            "crest_height_error,rmse,jacobian_ratio_min,jacobian_ratio_avg,eps_q_avg\n"
            "tt0,0,0,2.5,0.5,0,10,0,0,1,,\n"
            "tt1,1,0.495227,2.75,0.55,0.1,9,-0.1,0.127359,0.86,0.99,0.126\n"
            "pure-mpm,,,0.5,0.1,-0.8,10,0,0.470588,,,\n");

  // Without the reference run the errors and RMSE are not defined: empty cells.
  const std::string without = sweep_csv(c, runs, "tt9");
  EXPECT_NE(without.find("tt1,1,0.495227,2.75,0.55,,9,,,0.86,0.99,0.126\n"), std::string::npos)
      << without;

  const std::string md = sweep_markdown(c, runs, "tt0");
  EXPECT_NE(md.find("| tt1 |"), std::string::npos) << md;
  EXPECT_NE(md.find("+10.0 %"), std::string::npos) << md;  // R_N error of tt1
  EXPECT_NE(md.find("-80.0 %"), std::string::npos) << md;  // R_N error of pure-mpm
}

TEST(SweepTable, ProfilesAreListedPerBinWithTheirCentres) {
  const std::vector<RunMetrics> runs{run("tt0", 0.0, {10, 8.5}, 3.0, 5.0)};
  EXPECT_EQ(profiles_csv(runs), "run,bin,x_centre,height\ntt0,0,1,10\ntt0,1,3,8.5\n");
}

}  // namespace
}  // namespace slide::tools
