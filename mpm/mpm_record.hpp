// The restart record of mpm-solve's checkpoints (common/run/restart_record.hpp): the
// solver's clock beyond time and step, the guard's references and the step rule, as the
// /solver group of a kind "mpm" checkpoint holds them, with the settings the run ran with.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "common/io/checkpoint.hpp"
#include "common/run/restart_record.hpp"
#include "common/run/stability_guard.hpp"
#include "mpm/domain.hpp"
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
  /// The ranks' slabs when the checkpoint was written on several ("0 25 200": the first
  /// cell column of each rank, then the grid's end; empty on one). A restart on as many
  /// ranks takes them, so that each rank holds the particles it held, in the order it
  /// held them, and the run continues bit for bit.
  std::string slab_cuts;
  /// The particles each rank held then ("16010 15990 0 0": each rank's active rows, then
  /// each rank's frozen rows; empty on one rank). Particles that crossed a cut in the
  /// checkpoint's last step are still held by the rank they left: a restart gives every
  /// row back to its holder (HeldRows).
  std::string slab_rows;
};

/// The record of the solver's state (collective: the frozen count is every rank's).
MpmRecord restart_record(const MpmSolver& solver, const RunReferences& references);

/// The /solver group of a checkpoint of the solver's state: the record and the settings.
SolverSettings write_record(const MpmSolver& solver, const RunReferences& references);

/// The record of a kind "mpm" checkpoint (its particle rows need not be read), every
/// entry checked; Error naming `source` and the key otherwise, or the kind.
MpmRecord read_mpm_record(const ParticleCheckpoint& checkpoint, const std::string& source);

/// The slabs and holders of a checkpoint written on several ranks (MpmRecord::slab_cuts,
/// slab_rows) when the restart runs on as many (`ranks`), else none (the slabs are then
/// balanced afresh); `first_row` is where this rank's part of the file's `file_rows`
/// begins. Error naming `source` when the texts are not lists of cell columns and of row
/// counts adding up to the file's; the cuts are checked against the grid when the solver
/// takes them.
std::optional<Decomposition> restart_slabs(const MpmRecord& record, std::size_t file_rows,
                                           std::size_t first_row, int ranks,
                                           const std::string& source);

/// The solver's clock and the references a run continues from.
void restore(const MpmRecord& record, const CheckpointHeader& header, SolverClock& clock,
             RunReferences& references);

/// The settings a run with `settings` and the step rule (`time_step`, `courant`) records
/// in its checkpoints' /solver group, which a restart compares with its own
/// (run::changed_settings) to say what an edited case changed.
SolverSettings ran_with(const MpmSettings& settings, double time_step, double courant);

}  // namespace slide::mpm
