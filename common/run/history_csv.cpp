#include "common/run/history_csv.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "common/base/error.hpp"
#include "common/io/atomic_file.hpp"
#include "common/run/output_schedule.hpp"

namespace slide::run {

namespace {

std::vector<std::string> split_csv_line(const std::string& line) {
  std::vector<std::string> cells;
  std::stringstream stream(line);
  std::string cell;
  while (std::getline(stream, cell, ',')) {
    const auto begin = cell.find_first_not_of(" \t\r");
    const auto end = cell.find_last_not_of(" \t\r");
    cells.push_back(begin == std::string::npos ? "" : cell.substr(begin, end - begin + 1));
  }
  return cells;
}

double parse_number(const std::string& text, const std::filesystem::path& path, int line) {
  if (text.empty() || text == "nan" || text == "NaN") return std::nan("");
  try {
    std::size_t used = 0;
    const double value = std::stod(text, &used);
    if (used != text.size()) throw std::invalid_argument(text);
    return value;
  } catch (const std::exception&) {
    throw Error("{}:{}: \"{}\" is not a number", path.string(), line, text);
  }
}

}  // namespace

HistoryRows read_history(const std::filesystem::path& path, const std::string& what,
                         const std::vector<std::string>& names,
                         const std::vector<std::string>& optional) {
  std::ifstream in(path);
  if (!in) throw Error("{}: cannot open {}", path.string(), what);
  std::string line;
  if (!std::getline(in, line)) throw Error("{}: empty file, expected a header line", path.string());
  const auto header = split_csv_line(line);
  std::vector<std::size_t> index;
  for (const auto& name : names) {
    const auto found = std::find(header.begin(), header.end(), name);
    if (found == header.end()) throw Error("{}: missing column {}", path.string(), name);
    index.push_back(static_cast<std::size_t>(found - header.begin()));
  }
  const std::size_t absent = header.size();
  for (const auto& name : optional) {
    const auto found = std::find(header.begin(), header.end(), name);
    index.push_back(found == header.end() ? absent
                                          : static_cast<std::size_t>(found - header.begin()));
  }
  HistoryRows rows;
  int line_number = 1;
  while (std::getline(in, line)) {
    ++line_number;
    if (line.empty() || line == "\r") continue;
    const auto cells = split_csv_line(line);
    if (cells.size() != header.size()) {
      throw Error("{}:{}: {} cells, expected {}", path.string(), line_number, cells.size(),
                  header.size());
    }
    std::vector<double> values;
    for (std::size_t i : index) {
      values.push_back(i == absent ? std::nan("") : parse_number(cells[i], path, line_number));
    }
    rows.push_back(std::move(values));
  }
  return rows;
}

HistoryCsv::HistoryCsv(std::filesystem::path path, std::vector<std::string> columns)
    : path_(std::move(path)), columns_(std::move(columns)) {}

void HistoryCsv::resume(double time, const Logger& logger) {
  rows_.clear();
  if (!std::filesystem::exists(path_)) {
    logger.warning("{}: not found; the history restarts at t = {:.3f} s", path_.string(), time);
    return;
  }
  HistoryRows kept;
  try {
    // Every column but time is optional: a history an older version wrote, with fewer
    // columns, continues with those columns NaN.
    const std::vector<std::string> rest(columns_.begin() + 1, columns_.end());
    kept = read_history(path_, "the history", {columns_.front()}, rest);
  } catch (const Error& e) {
    logger.warning("{}; the history is replaced", e.what());
    return;
  }
  for (auto& row : kept) {
    if (row.front() > time + OutputSchedule::tolerance(time)) break;
    rows_.push_back(std::move(row));
  }
}

void HistoryCsv::add(std::vector<double> row) {
  if (row.size() != columns_.size()) {
    throw Error("{}: a row of {} values for {} columns", path_.string(), row.size(),
                columns_.size());
  }
  rows_.push_back(std::move(row));
  write();
}

void HistoryCsv::write() const {
  std::string text = fmt::format("{}\n", fmt::join(columns_, ","));
  for (const auto& row : rows_) text += fmt::format("{}\n", fmt::join(row, ","));
  write_text_atomically(path_, text);
}

}  // namespace slide::run
