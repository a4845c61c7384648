// History CSVs: what a stage writes reads back exactly, restarts keep the rows up to
// their time, older files with fewer columns continue, foreign files are replaced.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>

#include <gtest/gtest.h>

#include "common/base/error.hpp"
#include "common/run/history_csv.hpp"

namespace slide::run {
namespace {

namespace fs = std::filesystem;

fs::path scratch(const std::string& name) {
  const fs::path dir = fs::path(SLIDE_BINARY_DIR) / "test-scratch" / "history_csv" / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

std::string text_of(const fs::path& path) {
  std::ifstream in(path);
  std::string text, line;
  while (std::getline(in, line)) text += line + '\n';
  return text;
}

TEST(HistoryCsv, EveryValueReadsBackToTheSameDouble) {
  const fs::path file = scratch("round-trip") / "h.csv";
  HistoryCsv csv(file, {"time", "a", "b"});
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<std::vector<double>> rows{
      {0.1, 1.0 / 3.0, 12.0}, {0.30000000000000004, 6.02214076e23, nan}, {0.4, -1e-300, 0.0}};
  for (const auto& row : rows) csv.add(row);
  EXPECT_EQ(text_of(file).substr(0, text_of(file).find('\n')), "time,a,b");
  const HistoryRows back = read_history(file, "the test history", {"time", "a", "b"});
  ASSERT_EQ(back.size(), rows.size());
  for (std::size_t i = 0; i < rows.size(); ++i) {
    for (std::size_t j = 0; j < 3; ++j) {
      if (std::isnan(rows[i][j])) {
        EXPECT_TRUE(std::isnan(back[i][j]));
      } else {
        EXPECT_EQ(back[i][j], rows[i][j]) << "row " << i << " column " << j;
      }
    }
  }
  // Integers print as integers (n_elements_yielding), NaN as "nan".
  EXPECT_NE(text_of(file).find("0.1,0.3333333333333333,12\n"), std::string::npos) << text_of(file);
  EXPECT_NE(text_of(file).find(",nan\n"), std::string::npos);
  EXPECT_THROW(csv.add({1.0, 2.0}), Error);  // a row of the wrong width
}

TEST(HistoryCsv, AResumeKeepsTheRowsUpToItsTimeAndFillsMissingColumnsWithNaN) {
  const fs::path file = scratch("resume") / "h.csv";
  // An older version's file: no column b, and a row after the restart time.
  std::ofstream(file) << "time,a\n0,1\n0.5,2\n1.0000000001,3\n1.5,4\n";
  HistoryCsv csv(file, {"time", "a", "b"});
  const Logger quiet("test", true);
  csv.resume(1.0, quiet);
  ASSERT_EQ(csv.rows().size(), 3U);  // 1.0000000001 is 1 s within the schedule's tolerance
  EXPECT_EQ(csv.rows()[1][1], 2.0);
  EXPECT_TRUE(std::isnan(csv.rows()[1][2]));
  csv.add({1.1, 5.0, 6.0});
  EXPECT_EQ(text_of(file), "time,a,b\n0,1,nan\n0.5,2,nan\n1.0000000001,3,nan\n1.1,5,6\n");
}

TEST(HistoryCsv, AForeignOrMissingFileStartsAnEmptyHistory) {
  const fs::path dir = scratch("foreign");
  const Logger quiet("test", true);
  std::ofstream(dir / "foreign.csv") << "x,y\n1,2\n";
  HistoryCsv foreign(dir / "foreign.csv", {"time", "a"});
  foreign.resume(1.0, quiet);
  EXPECT_TRUE(foreign.rows().empty());
  std::ofstream(dir / "damaged.csv") << "time,a\n0,1\n0.5,x\n";
  HistoryCsv damaged(dir / "damaged.csv", {"time", "a"});
  damaged.resume(1.0, quiet);
  EXPECT_TRUE(damaged.rows().empty());
  HistoryCsv missing(dir / "missing.csv", {"time", "a"});
  missing.resume(1.0, quiet);
  EXPECT_TRUE(missing.rows().empty());
}

TEST(HistoryCsv, ReadingNamesTheFileAndTheFault) {
  const fs::path dir = scratch("errors");
  std::ofstream(dir / "short.csv") << "time,a\n0,1\n0.5\n";
  try {
    read_history(dir / "short.csv", "the history", {"time"});
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("short.csv:3: 1 cells, expected 2"), std::string::npos)
        << e.what();
  }
  try {
    read_history(dir / "short.csv", "the history", {"time", "ke_over_pe0"});
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("missing column ke_over_pe0"), std::string::npos);
  }
}

}  // namespace
}  // namespace slide::run
