// What mpm-solve writes (docs/contract.md): checkpoints OUT/mpm_t<T>.h5 and OUT/mpm_final.h5
// (kind "mpm", with the grid/solver settings and counters a restart needs), the history
// OUT/mpm_history.csv, and ParaView files OUT/vtk/mpm_<step>.vtu + OUT/mpm.pvd.
#pragma once

#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "common/base/log.hpp"
#include "common/io/checkpoint.hpp"
#include "common/io/vtk_output.hpp"
#include "common/run/history_csv.hpp"
#include "common/run/stability_guard.hpp"
#include "common/settings/metrics_spec.hpp"
#include "mpm/mpm_record.hpp"
#include "mpm/mpm_solver.hpp"

namespace slide::mpm {

/// Writes the solver's state as a kind "mpm" checkpoint (atomically, common/io/checkpoint.hpp)
/// straight from the solver's particle arrays, which it borrows for the write instead of
/// copying them (a copy would double the particle memory at every checkpoint). The case's
/// `fingerprint` goes into the restart record (common/input/case_fingerprint.hpp).
void write_mpm_checkpoint(const std::filesystem::path& path, MpmSolver& solver,
                          const RunReferences& references, const std::string& case_name,
                          const TransferSettings& transfer,
                          const std::optional<CheckpointMotion>& motion = std::nullopt,
                          const SolverSettings& fingerprint = {});

/// mpm_history.csv: one row per output step with the docs/contract.md columns, through
/// common/run/history_csv.hpp. The runout is measured as sweep.csv measures it (docs/method.md
/// §6, over the case's foundation level). On restart the rows after the restart time
/// are dropped.
class MpmHistory {
 public:
  MpmHistory(std::filesystem::path path, const MetricsSpec& metrics);
  void resume(double time, const Logger& logger) { csv_.resume(time, logger); }
  /// The row of the solver's current state; nothing when a row of that time (or a later
  /// one) is there already (a restart's first output, or the final row).
  void write(const MpmSolver& solver, double pe0);

 private:
  run::HistoryCsv csv_;
  MetricsSpec metrics_;
};

/// OUT/vtk/mpm_<step>.vtu with every particle field, registered in OUT/mpm.pvd.
class VtkWriter {
 public:
  VtkWriter(const std::filesystem::path& output_dir, std::optional<double> resume_time);
  void write(const MpmSolver& solver);

 private:
  /// On several ranks: each rank's piece, then the root's .pvtu joining them, each step
  /// ending every rank when it failed on one (Ranks::together).
  void write_pieces(const Ranks& ranks, const std::string& name, double time,
                    std::span<const Vec2> coordinates, const std::vector<VtkField>& fields);

  std::filesystem::path folder_;
  PvdCollection collection_;
};

}  // namespace slide::mpm
