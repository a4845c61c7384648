// mpm-solve's stage (run::Stage, common/run/stage.hpp): where the particles come from (a
// particle file, a restart, or the case geometry for pure MPM), the initial state of the
// loop (pure MPM's initial stresses, the switch to the MPM models, the guard's
// references), the steps with the rest detection, and at each output the guard, the
// history row, the VTK frame, the recorders' files and the checkpoint. run_mpm (mpm_run.hpp) sets
// it up from the plan and hands it to run::execute.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <type_traits>

#include "common/base/error.hpp"
#include "common/base/log.hpp"
#include "common/base/ranks.hpp"
#include "common/run/stage.hpp"
#include "common/run/thread_tuner.hpp"
#include "mpm/mpm_output.hpp"
#include "mpm/mpm_plan.hpp"
#include "mpm/mpm_solver.hpp"
#include "mpm/particle_recorders.hpp"

namespace slide::mpm {

/// What a run starts from: the particles (this rank's part), the solver's clock and the
/// guard's references (a restart's, else set at the start), the transfer and the base
/// motion the file records.
struct Start {
  Particles particles;
  SolverClock clock;
  RunReferences references;
  TransferSettings transfer;
  std::optional<CheckpointMotion> motion;
  std::size_t file_rows = 0;  ///< a particle file's rows (0: none read)
  std::size_t first_row = 0;  ///< where this rank's part of them begins
};

/// The particles and the state `plan` starts from (each rank its part of the rows).
Start load_start(const MpmPlan& plan, const Logger& log, const Ranks& ranks);

/// f() on every rank, as one decision (collective): when it throws Error on some ranks
/// (a bad row in one rank's part of a particle file), every rank throws the message of
/// the lowest of them, so that the run ends with its one line instead of an abort.
template <class F>
std::invoke_result_t<F> agreed(const Ranks& ranks, F&& f) {
  std::invoke_result_t<F> result{};
  std::optional<std::string> problem;
  try {
    result = f();
  } catch (const Error& e) {
    problem = e.what();
  }
  if (const auto first = ranks.first_problem(problem)) throw Error("{}", *first);
  return result;
}

/// The step: the case's, or the Courant step at the particles' current densities, taken
/// anew every step (mpm/README.md, "Time step"). The one place the rule is applied.
double time_step(const MpmSpec& spec, const MpmSolver& solver);

/// Particles on every rank together (collective).
std::size_t total_particles(const MpmSolver& solver);

/// Warnings about particles leaving the grid, rate-limited: the first exit at once, then
/// one warning per checkpoint for the exits since the last warning (a body pouring over
/// the grid's edge loses particles on hundreds of steps), and the run's total at its end.
class ExitLog {
 public:
  ExitLog(const Logger& log, ParticleExit mode)
      : log_(log), fate_(mode == ParticleExit::freeze ? "were frozen" : "were removed") {}

  /// `count` particles left the grid in the step that ended at `time`.
  void add(std::size_t count, double time) {
    if (count == 0) return;
    total_ += count;
    if (total_ == count) {
      first_exit_ = time;
      log_.warning(
          "{} particle{} left the grid at t = {:.4f} s and {}; further exits are reported at "
          "the checkpoints",
          count, plural(count), time, fate_);
      return;
    }
    if (unreported_ == 0) first_unreported_ = time;
    unreported_ += count;
  }
  /// At a checkpoint: the exits since the last warning.
  void report(double time) {
    if (unreported_ == 0) return;
    log_.warning(
        "{} more particle{} left the grid between t = {:.4f} and {:.4f} s and {} ({} in all)",
        unreported_, plural(unreported_), first_unreported_, time, fate_, total_);
    unreported_ = 0;
  }
  /// At the end of the run: the last exits not reported yet, and the total.
  void finish(double time) {
    if (total_ == 0) return;
    report(time);
    log_.warning("{} particle{} left the grid in this run (the first at t = {:.4f} s) and {}",
                 total_, plural(total_), first_exit_, fate_);
  }

 private:
  static const char* plural(std::size_t n) { return n == 1 ? "" : "s"; }

  const Logger& log_;
  const char* fate_;
  std::size_t total_ = 0, unreported_ = 0;
  double first_exit_ = 0.0, first_unreported_ = 0.0;
};

/// mpm-solve's steps and outputs: steps of the case's Δt or of the Courant step at the
/// particles' current densities, landing on the schedule's times; the rest detection; at
/// each output the history row, the VTK frame, the checkpoint.
class MpmStage final : public run::Stage {
 public:
  MpmStage(const MpmPlan& plan, MpmSolver& solver, Start& start, const Logger& log);

  double time() const override { return solver_.clock().time; }
  std::int64_t step() const override { return solver_.clock().step; }
  void open_outputs(bool resume) override;
  run::StartOutput start() override;
  bool advance_to(double stop) override;
  std::optional<std::string> check_stability() override;
  void write_output(const run::OutputStep& step) override;
  void finish() override;
  run::Work work() const override;
  run::OutputSizes output_sizes() const override;

 private:
  void start_recorders(bool resume);

  const MpmPlan& plan_;
  MpmSolver& solver_;
  Start& start_;
  const Logger& log_;
  std::optional<MpmHistory> history_;
  std::optional<VtkWriter> vtk_;
  std::optional<ParticleRecorders> recorders_;
  std::optional<Progress> progress_;
  ExitLog exits_;
  std::int64_t steps_ = 0;
  double particle_steps_ = 0.0;
  run::ThreadTuner threads_;  ///< the OpenMP threads of each step
};

}  // namespace slide::mpm
