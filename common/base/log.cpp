#include "common/base/log.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <unistd.h>

#include "common/base/error.hpp"

namespace slide {

void Logger::write_to(const std::filesystem::path& file) const {
  if (muted_) return;
  std::FILE* handle = std::fopen(file.c_str(), "a");
  if (handle == nullptr) throw Error("{}: cannot open the run's log file", file.string());
  file_.reset(handle, [](std::FILE* f) { std::fclose(f); });
}

void Logger::to_file(std::string_view line) const {
  if (!file_) return;
  fmt::print(file_.get(), "{}\n", line);
  std::fflush(file_.get());
}

namespace {

std::string format_duration(double seconds) {
  if (!std::isfinite(seconds) || seconds < 0) return "?";
  const auto s = static_cast<long>(std::lround(seconds));
  if (s < 60) return fmt::format("{}s", s);
  if (s < 3600) return fmt::format("{}m{:02}s", s / 60, s % 60);
  return fmt::format("{}h{:02}m", s / 3600, (s % 3600) / 60);
}

}  // namespace

Progress::Progress(const Logger& logger, std::string label, double start, double end)
    : logger_(logger),
      label_(std::move(label)),
      start_(start),
      end_(end),
      terminal_(::isatty(STDOUT_FILENO) == 1) {}

Progress::~Progress() {
  logger_.close_progress_line();
}

double Progress::elapsed_seconds() const {
  return std::chrono::duration<double>(Clock::now() - started_at_).count();
}

void Progress::update(double time, std::int64_t step, std::string_view status) {
  const auto now = Clock::now();
  const double since_print = std::chrono::duration<double>(now - last_print_).count();
  const double span = end_ - start_;
  const double fraction = span > 0 ? std::clamp((time - start_) / span, 0.0, 1.0) : 1.0;
  const double elapsed = elapsed_seconds();
  const double eta = fraction > 0 ? elapsed * (1.0 - fraction) / fraction
                                  : std::numeric_limits<double>::quiet_NaN();
  const auto plain_line = [&] {
    return fmt::format("{}: {} t={:.3f}/{:.3f} s ({:.0f}%) step {} wall {} eta {} {}",
                       logger_.prefix(), label_, time, end_, 100.0 * fraction, step,
                       format_duration(elapsed), format_duration(eta), status);
  };
  // The log file gets a plain line every 10 %, whatever the console shows.
  const int decile = static_cast<int>(std::floor(10.0 * fraction + 1e-9));
  if (decile > last_decile_logged_) {
    last_decile_logged_ = decile;
    logger_.to_file(plain_line());
  }
  if (logger_.quiet()) return;
  if (terminal_) {
    if (since_print < 0.2) return;
    fmt::print(stdout, "\r{}: {} t={:.3f}/{:.3f} s {:5.1f}% step {} wall {} eta {} {}\033[K",
               logger_.prefix(), label_, time, end_, 100.0 * fraction, step,
               format_duration(elapsed), format_duration(eta), status);
    logger_.progress_line_open_ = true;
  } else {
    // Deciles counted on the fraction reached, so the lines fall at 10 %, 20 %, ... 100 %
    // whatever the step length (a difference of fractions would drift by a step each time).
    if (decile <= last_decile_printed_ && since_print < 30.0) return;
    last_decile_printed_ = decile;
    fmt::print(stdout, "{}\n", plain_line());
  }
  std::fflush(stdout);
  last_print_ = now;
}

void Progress::finish() {
  if (finished_) return;
  finished_ = true;
  logger_.info("{} done in {}", label_, format_duration(elapsed_seconds()));
}

}  // namespace slide
