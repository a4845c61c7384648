// What mpm-solve writes (docs/contract.md): checkpoints OUT/mpm_t<T>.h5 and OUT/mpm_final.h5
// (kind "mpm", with the grid/solver settings and counters a restart needs), the history
// OUT/mpm_history.csv, and ParaView files OUT/vtk/mpm_<step>.vtu + OUT/mpm.pvd.
#pragma once

#include <filesystem>
#include <string>

#include "common/base/log.hpp"
#include "common/settings/metrics_spec.hpp"
#include "common/io/checkpoint.hpp"
#include "common/io/vtk_output.hpp"
#include "common/run/history_csv.hpp"
#include "common/run/restart_record.hpp"
#include "common/run/stability_guard.hpp"
#include "mpm/mpm_solver.hpp"

namespace slide::mpm {

/// References of the instability guard and the rest detection, fixed at the start of the
/// run (t = 0 for pure MPM, the particle file's time otherwise) and carried by restarts.
struct RunReferences {
  double pe0 = 0.0;               ///< PE_0, J/m (docs/contract.md)
  double reference_height = 0.0;  ///< H of the speed bound sqrt(2 g H), m
  run::EnergyReference energy;    ///< KE + PE + elastic at the start, the releasable energy
  double rest_timer = 0.0;        ///< s spent with KE/PE0 below the rest threshold
  double time_step = 0.0;         ///< the case's fixed Δt, s (0: the Courant step)
  double courant = 0.0;           ///< C of the Courant step (with time_step 0)
};

/// The restart record of an "mpm" checkpoint (common/run/restart_record.hpp): the solver's
/// clock beyond time and step, the guard's references and the step rule.
struct MpmRecord : run::RunRecord {
  double previous_time_step = 0.0;  ///< Δt_{n−1}, s
  std::int64_t steps_since_sort = 0;
  bool sorted_once = false;
  std::int64_t frozen_particles = 0;  ///< the file's last rows
  double reference_height = 0.0;      ///< H of the speed bound, m
  double rest_timer = 0.0;            ///< s
  double time_step = 0.0;             ///< the case's fixed Δt, s (0: Courant)
  double courant = 0.0;
};

/// Writes the solver's state as a kind "mpm" checkpoint (atomically, common/io/checkpoint.hpp)
/// straight from the solver's particle arrays, which it borrows for the write instead of
/// copying them (a copy would double the particle memory at every checkpoint).
void write_mpm_checkpoint(const std::filesystem::path& path, MpmSolver& solver,
                          const RunReferences& references, const std::string& case_name,
                          const TransferSettings& transfer,
                          const std::optional<CheckpointMotion>& motion = std::nullopt);

/// Restores the counters and references of a kind "mpm" checkpoint; Error naming
/// `source` and the /solver key when one is missing, of the wrong type or out of range.
void read_restart_state(const ParticleCheckpoint& checkpoint, const std::string& source,
                        SolverClock& clock, RunReferences& references);

/// The settings a run with `settings` and the step rule (`time_step`, `courant`) records
/// in its checkpoints' /solver group, which a restart compares with its own
/// (run::changed_settings) to say what an edited case changed.
SolverSettings ran_with(const MpmSettings& settings, double time_step, double courant);

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
  std::filesystem::path folder_;
  PvdCollection collection_;
};

}  // namespace slide::mpm
