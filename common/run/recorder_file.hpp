// One recorder's CSV (fem/recorders.hpp, mpm/particle_recorders.hpp): a header of column
// names, then a row of numbers at each recorded step, kept in memory between the
// stage's checkpoints and written whole and atomically at each of them and at the end,
// so that a killed run leaves complete files up to its last checkpoint, from which a
// restart continues them. What the columns hold is each stage's; the cadence, the
// restart, the file and the bound on what a run's recorders may hold are here once.
#pragma once

#include <filesystem>
#include <span>
#include <string>

#include "common/base/log.hpp"

namespace slide::run {

class RecorderFile {
 public:
  /// `header` without the line end ("time,n12_ux,…"); `every` s between rows (0: every step).
  RecorderFile(std::string name, std::string header, double every);

  /// The longest recorder name: <name>.csv must be a file name (255 bytes).
  static constexpr std::size_t max_name_bytes = 200;
  /// A number as the rows print it, about: "-1.2345678901234567e-05,".
  static constexpr double bytes_per_value = 24.0;
  /// What a run's recorders may hold: 1 GB, a few hundred thousand rows of a few hundred
  /// points; beyond it a cadence or a set is a mistake, not a plan (and the rows, kept in
  /// memory, would crowd the run out).
  static constexpr std::size_t limit_bytes = 1'000'000'000;

  const std::string& name() const { return name_; }
  double every() const { return every_; }
  std::size_t columns() const;

  /// Whether a row is due at time t.
  bool due(double t) const;
  /// Starts the row of time t and moves the cadence past t; then `add` each value and `end_row`.
  void begin_row(double t);
  void add(double value);
  void end_row() { rows_ += '\n'; }

  /// On restart: keeps the rows of folder/<name>.csv up to `time` when its header is this
  /// recorder's; otherwise (no file, other columns) starts afresh at `time`, with a warning.
  void resume(const std::filesystem::path& folder, double time, const Logger& logger);
  /// Rewrites folder/<name>.csv atomically.
  void write(const std::filesystem::path& folder) const;

  /// The bytes the rows of a run of `duration` s in steps of `step` s will take; a
  /// cadence below the step becomes every step.
  double planned_bytes(double duration, double step);

 private:
  std::string name_;
  std::string header_;
  double every_ = 0.0;
  double next_ = 0.0;
  std::string rows_;
};

/// Error naming `what` ("fem.recorders") when the recorders of a run of `duration` s in
/// steps of `step` s would hold more than `limit` bytes, before any file is written.
void bound_recorders(std::span<RecorderFile> files, double duration, double step,
                     std::string_view what, std::size_t limit = RecorderFile::limit_bytes);

/// Error naming `what` when a recorder's name is longer than RecorderFile::max_name_bytes.
void check_recorder_name(const std::string& name, std::string_view what);

}  // namespace slide::run
