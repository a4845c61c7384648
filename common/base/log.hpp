// Console output of the programs. Messages go to stdout as "program: text"; warnings
// go to stderr and are never silenced. `--quiet` silences info and progress only; a
// muted logger (the non-root ranks of an MPI run) prints nothing. Once a run has its
// output folder, every line also goes to the folder's log file (write_to), --quiet or
// not, progress as plain lines every 10 %.
// The logger is an object owned by main and passed down: no global state.
#pragma once

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <string_view>

#include <fmt/format.h>

namespace slide {

class Logger {
 public:
  /// `muted`: prints nothing at all, warnings and results included (the ranks other
  /// than the root of a run on several, whose lines the root prints once).
  explicit Logger(std::string program, bool quiet = false, bool muted = false)
      : program_(std::move(program)), prefix_(program_), quiet_(quiet || muted), muted_(muted) {}

  bool quiet() const { return quiet_; }
  const std::string& program() const { return program_; }
  /// What starts each line: the program, and the run's tag when it has one
  /// ("mpm-solve[tt2]: …", --tag): under make -j two runs' lines tell themselves apart.
  const std::string& prefix() const { return prefix_; }
  void set_tag(const std::string& tag) {
    prefix_ = tag.empty() ? program_ : program_ + "[" + tag + "]";
  }

  /// From now on every line also goes to `file` (appended: a restart into the same
  /// folder continues the log). Nothing for a muted logger. Error (one line) when the
  /// file cannot be opened.
  void write_to(const std::filesystem::path& file) const;
  /// A line for the log file only (progress lines of a terminal run).
  void to_file(std::string_view line) const;

  template <typename... Args>
  void info(fmt::format_string<Args...> format, Args&&... args) const {
    if (quiet_ && !file_) return;
    const std::string line =
        fmt::format("{}: {}", prefix_, fmt::format(format, std::forward<Args>(args)...));
    to_file(line);
    if (quiet_) return;
    close_progress_line();
    fmt::print(stdout, "{}\n", line);
    std::fflush(stdout);
  }

  template <typename... Args>
  void warning(fmt::format_string<Args...> format, Args&&... args) const {
    if (muted_) return;
    const std::string line =
        fmt::format("{}: warning: {}", prefix_, fmt::format(format, std::forward<Args>(args)...));
    to_file(line);
    close_progress_line();
    fmt::print(stderr, "{}\n", line);
  }

  /// Always printed (docs/contract.md: the summary line must reach scripts even with --quiet).
  template <typename... Args>
  void result(fmt::format_string<Args...> format, Args&&... args) const {
    if (muted_) return;
    const std::string line = fmt::format(format, std::forward<Args>(args)...);
    to_file(line);
    close_progress_line();
    fmt::print(stdout, "{}\n", line);
    std::fflush(stdout);
  }

 private:
  friend class Progress;

  /// A progress line redrawn in place on a terminal has no newline yet: end it before
  /// any other message, so the message starts a line of its own.
  void close_progress_line() const {
    if (!progress_line_open_) return;
    fmt::print(stdout, "\n");
    std::fflush(stdout);
    progress_line_open_ = false;
  }

  std::string program_;
  std::string prefix_;
  bool quiet_;
  bool muted_ = false;
  mutable bool progress_line_open_ = false;
  /// The run's log file (write_to), shared by copies of the logger.
  mutable std::shared_ptr<std::FILE> file_;
};

/// Progress of a time loop on the simulation clock, from `start` to `end` seconds.
/// On a terminal: one line redrawn in place with percentage, step, wall time and ETA,
/// at most five times a second. Otherwise (logs, CI, Make): a plain line every 10 % or
/// every 30 s of wall time, whichever comes first. Silent with --quiet.
class Progress {
 public:
  Progress(const Logger& logger, std::string label, double start, double end);
  ~Progress();
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  /// Reports the simulation time reached and a short status (e.g. "KE/PE0 0.013").
  void update(double time, std::int64_t step, std::string_view status = {});
  /// Ends the line (terminal mode) and prints the final wall time.
  void finish();

  double elapsed_seconds() const;

 private:
  using Clock = std::chrono::steady_clock;
  const Logger& logger_;
  std::string label_;
  double start_, end_;
  bool terminal_;
  bool finished_ = false;
  Clock::time_point started_at_ = Clock::now();
  Clock::time_point last_print_ = started_at_;
  int last_decile_printed_ = 0;
  int last_decile_logged_ = 0;  ///< in the log file
};

}  // namespace slide
