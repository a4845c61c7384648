// History CSVs (docs/contract.md: fem_history.csv, mpm_history.csv): a header of column
// names, then one row of numbers per output step. Both stages write them through
// HistoryCsv and every reader (restarts, tools/) reads them through read_history, so the
// format has one definition: numbers in the shortest form that reads back to the same
// double ("nan" where a quantity is undefined), the file rewritten whole and atomically
// after each row, so that a run stopped at any moment leaves a complete history.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "common/base/log.hpp"

namespace slide::run {

/// The rows of a history, each in the order of the columns asked for.
using HistoryRows = std::vector<std::vector<double>>;

/// The columns `names` (required: Error naming the file and the column when absent)
/// and then `optional` (NaN where the file has no such column) of the history at
/// `path`, row by row; blank lines are skipped. `what` names the file in errors ("the
/// FE history"). Error on a row with the wrong number of cells or a cell that is not a
/// number ("nan" and an empty cell are NaN).
HistoryRows read_history(const std::filesystem::path& path, const std::string& what,
                         const std::vector<std::string>& names,
                         const std::vector<std::string>& optional = {});

class HistoryCsv {
 public:
  HistoryCsv(std::filesystem::path path, std::vector<std::string> columns);

  /// On restart: keeps the rows of the existing file up to `time` (its columns matched
  /// by name; a column the file lacks comes back NaN). A missing file, or one that is
  /// not such a history, starts an empty one, with a warning.
  void resume(double time, const Logger& logger);
  /// Appends a row (one value per column) and rewrites the file.
  void add(std::vector<double> row);

  const HistoryRows& rows() const { return rows_; }
  const std::filesystem::path& path() const { return path_; }

 private:
  void write() const;

  std::filesystem::path path_;
  std::vector<std::string> columns_;
  HistoryRows rows_;
};

}  // namespace slide::run
