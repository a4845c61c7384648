#include "common/io/motion_file.hpp"

#include <charconv>
#include <cmath>
#include <fstream>
#include <string>

#include "common/base/error.hpp"

namespace slide {

namespace {

/// The numbers of one line (comma or white space between them).
std::vector<double> numbers_of(std::string_view line, const std::string& where) {
  std::vector<double> values;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() &&
           (line[i] == ' ' || line[i] == '\t' || line[i] == ',' || line[i] == '\r')) {
      ++i;
    }
    if (i == line.size()) break;
    std::size_t end = i;
    while (end < line.size() && line[end] != ' ' && line[end] != '\t' && line[end] != ',' &&
           line[end] != '\r') {
      ++end;
    }
    const std::string_view token = line.substr(i, end - i);
    double value = 0.0;
    const auto [ptr, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
    if (ec != std::errc() || ptr != token.data() + token.size() || !std::isfinite(value)) {
      throw Error("{}: \"{}\" is not a finite number", where, token);
    }
    values.push_back(value);
    i = end;
  }
  return values;
}

}  // namespace

AccelerationRecord read_motion_file(const std::filesystem::path& path, double scale) {
  std::error_code ec;
  const auto size = std::filesystem::file_size(path, ec);
  if (ec) throw Error("{}: cannot read the motion file ({})", path.string(), ec.message());
  if (size > max_motion_file_bytes) {
    throw Error("{}: {} bytes, larger than a motion file can be ({} bytes)", path.string(), size,
                max_motion_file_bytes);
  }
  std::ifstream in(path);
  if (!in) throw Error("{}: cannot open the motion file", path.string());
  AccelerationRecord record;
  std::string line;
  for (std::size_t number = 1; std::getline(in, line); ++number) {
    const std::string where = fmt::format("{}:{}", path.string(), number);
    const std::string_view text = std::string_view(line).substr(0, line.find('#'));
    const std::vector<double> values = numbers_of(text, where);
    if (values.empty()) continue;
    if (values.size() != 2) {
      throw Error("{}: {} numbers, expected 2 (time in s, acceleration)", where, values.size());
    }
    if (record.time.empty() && values[0] < 0.0) {
      throw Error("{}: the first time is {} s (expected ≥ 0)", where, values[0]);
    }
    if (!record.time.empty() && !(values[0] > record.time.back())) {
      throw Error("{}: time {} s does not follow {} s (times must increase)", where, values[0],
                  record.time.back());
    }
    record.time.push_back(values[0]);
    record.acceleration.push_back(values[1] * scale);
  }
  if (in.bad()) throw Error("{}: read error", path.string());
  if (record.time.size() < 2) {
    throw Error("{}: {} samples, a motion needs at least 2", path.string(), record.time.size());
  }
  return record;
}

}  // namespace slide
