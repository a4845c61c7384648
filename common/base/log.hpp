// Console output of the programs. Messages go to stdout as "program: text"; warnings
// go to stderr and are never silenced. `--quiet` silences info and progress only; a
// muted logger (the non-root ranks of an MPI run) prints nothing.
// The logger is an object owned by main and passed down: no global state.
#pragma once

#include <chrono>
#include <cstdio>
#include <string>
#include <string_view>

#include <fmt/format.h>

namespace slide {

class Logger {
 public:
  /// `muted`: prints nothing at all, warnings and results included (the ranks other
  /// than the root of a run on several, whose lines the root prints once).
  explicit Logger(std::string program, bool quiet = false, bool muted = false)
      : program_(std::move(program)), quiet_(quiet || muted), muted_(muted) {}

  bool quiet() const { return quiet_; }
  const std::string& program() const { return program_; }

  template <typename... Args>
  void info(fmt::format_string<Args...> format, Args&&... args) const {
    if (quiet_) return;
    close_progress_line();
    fmt::print(stdout, "{}: {}\n", program_, fmt::format(format, std::forward<Args>(args)...));
    std::fflush(stdout);
  }

  template <typename... Args>
  void warning(fmt::format_string<Args...> format, Args&&... args) const {
    if (muted_) return;
    close_progress_line();
    fmt::print(stderr, "{}: warning: {}\n", program_,
               fmt::format(format, std::forward<Args>(args)...));
  }

  /// Always printed (docs/contract.md: the summary line must reach scripts even with --quiet).
  template <typename... Args>
  void result(fmt::format_string<Args...> format, Args&&... args) const {
    if (muted_) return;
    close_progress_line();
    fmt::print(stdout, "{}\n", fmt::format(format, std::forward<Args>(args)...));
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
  bool quiet_;
  bool muted_ = false;
  mutable bool progress_line_open_ = false;
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
};

}  // namespace slide
