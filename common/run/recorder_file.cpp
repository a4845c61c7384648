#include "common/run/recorder_file.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
#include <limits>

#include <fmt/format.h>

#include "common/base/error.hpp"
#include "common/io/atomic_file.hpp"

namespace slide::run {

namespace {

/// The relative tolerance of one time (common/run/README.md, "One time tolerance").
double slack(double t) {
  return 1e-9 * std::max(1.0, t);
}

}  // namespace

RecorderFile::RecorderFile(std::string name, std::string header, double every)
    : name_(std::move(name)), header_(std::move(header) + '\n'), every_(every) {}

std::size_t RecorderFile::columns() const {
  return static_cast<std::size_t>(std::ranges::count(header_, ',')) + 1;
}

bool RecorderFile::due(double t) const {
  return !(every_ > 0.0) || t >= next_ - slack(t);
}

void RecorderFile::begin_row(double t) {
  while (every_ > 0.0 && next_ <= t + slack(t)) next_ += every_;
  fmt::format_to(std::back_inserter(rows_), "{}", t);
}

void RecorderFile::add(double value) {
  fmt::format_to(std::back_inserter(rows_), ",{}", value);
}

void RecorderFile::resume(const std::filesystem::path& folder, double time, const Logger& logger) {
  const auto path = folder / (name_ + ".csv");
  rows_.clear();
  next_ = time;
  std::ifstream in(path);
  if (!in) {
    logger.warning("{}: not found, the recorder starts at t = {:.3f} s", path.string(), time);
    return;
  }
  std::string line;
  std::getline(in, line);
  if (line + '\n' != header_) {
    logger.warning("{}: other columns than the case's recorder, started again at t = {:.3f} s",
                   path.string(), time);
    return;
  }
  double last = -std::numeric_limits<double>::infinity();
  while (std::getline(in, line)) {
    double t = 0.0;
    try {
      t = std::stod(line.substr(0, line.find(',')));
    } catch (const std::exception&) {
      break;  // a row a killed run left unfinished
    }
    if (t > time + slack(time)) break;
    rows_ += line + '\n';
    last = t;
  }
  if (every_ > 0.0 && std::isfinite(last)) next_ = last + every_;
}

void RecorderFile::write(const std::filesystem::path& folder) const {
  write_text_atomically(folder / (name_ + ".csv"), header_ + rows_);
}

double RecorderFile::planned_bytes(double duration, double step) {
  // A cadence below the step records at every step, as a cadence of 0 does (and a
  // cadence of 1e-15 s no longer spins on the clock's last digits).
  if (every_ < step) every_ = 0.0;
  const double rows = std::floor(duration / std::max(every_, step)) + 2.0;
  return rows * static_cast<double>(columns()) * bytes_per_value;
}

void bound_recorders(std::span<RecorderFile> files, double duration, double step,
                     std::string_view what, std::size_t limit) {
  double bytes = 0.0;
  for (RecorderFile& file : files) bytes += file.planned_bytes(duration, step);
  if (bytes > static_cast<double>(limit)) {
    throw Error(
        "{} would hold and write about {:.3g} GB over the run ({:.4g} s in steps of {:.3g} s), "
        "above the {:.3g} GB the project allows: give them a coarser `every` or fewer points",
        what, bytes / 1e9, duration, step, static_cast<double>(limit) / 1e9);
  }
}

void check_recorder_name(const std::string& name, std::string_view what) {
  if (name.size() > RecorderFile::max_name_bytes) {
    throw Error("{} \"{}…\": the name has {} bytes, at most {} (it names a file)", what,
                name.substr(0, 40), name.size(), RecorderFile::max_name_bytes);
  }
}

}  // namespace slide::run
