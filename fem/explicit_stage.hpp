// fem-solve's stage (run::Stage, common/run/stage.hpp): the FE phase from its start, the
// geostatic state (solved by the geostatic pre-stage of a fresh run, or read from a
// checkpoint), through the explicit failure stage (docs/method.md §3): the switch to the
// failure models, the shaking boundaries (§8), the steps (fixed, or the Courant step of
// the geometry lowered by the stiffness damping), and at each output the guard, the
// history row with the mesh quality, the VTK frame, the checkpoint, the recorders and the
// recommended transfer zone. run_fem (fem_solver.hpp) builds it from the plan and hands it
// to run::execute.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "common/base/log.hpp"
#include "common/physics/ground_motion.hpp"
#include "common/run/stage.hpp"
#include "fem/explicit_dynamics.hpp"
#include "fem/fem_model.hpp"
#include "fem/fem_output.hpp"
#include "fem/fem_plan.hpp"
#include "fem/recorders.hpp"
#include "fem/seismic_boundary.hpp"
#include "fem/stability_guard.hpp"

namespace slide::fem {

struct FemRunSummary {
  Index steps = 0;  ///< time steps taken by this run
  Index elements = 0;
  double wall_seconds = 0.0;
  double end_time = 0.0;
  /// From the whole history (including the rows before a restart):
  std::optional<double> last_time_in_zone;  ///< last output time inside the zone
  std::optional<double> zone_exit_time;     ///< first output time outside it
  /// First output time with an inverted element (is_inverted: det J < 0 at a corner, or zero area).
  std::optional<double> first_time_inverted;
  std::optional<double> first_time_jacobian_ratio_negative;  ///< (|J_t|/|J_0|)_min < 0
  double ke_over_pe0_max = 0.0;
  double ke_over_pe0_max_time = 0.0;
  double ke_over_pe0_end = 0.0;                    ///< at the last output step
  double max_displacement = 0.0;                   ///< largest |u| of a node at the end, m
  std::vector<std::filesystem::path> checkpoints;  ///< written by this run
};

/// What fem-solve writes besides the loop's rows and frames: its checkpoints (with the
/// restart record), the recorders, and the state at the last output inside the
/// recommended transfer zone (--checkpoint-at-zone-exit).
class FemOutputs {
 public:
  FemOutputs(const FemPlan& plan, const FemModel& model, const Logger& log)
      : plan_(plan), model_(model), log_(log) {}

  /// The history and VTK series (resumed up to `time` on restart).
  void open(bool resume, double time);
  FemHistory& history() { return *history_; }
  const FemHistory& history() const { return *history_; }
  VtkSeries* vtk() { return vtk_ ? &*vtk_ : nullptr; }
  std::unique_ptr<Recorders>& recorders() { return recorders_; }

  /// A kind "fem" checkpoint of `state` with `record` (the stage's boundary conditions).
  void write_checkpoint(const FemState& state, const FemRecord& record,
                        const std::optional<CheckpointMotion>& motion,
                        const std::filesystem::path& file, double pe0);
  const std::vector<std::filesystem::path>& written() const { return written_; }

  /// Keeps the state of the last output inside the recommended zone and, when the zone
  /// is left, writes it with `write` (a regular checkpoint of that time already serves).
  template <class Write>
  void track_zone(const HistoryRow& row, const FemState& state, Write&& write);
  /// At the start of the loop without an output (a restart): the zone's state so far.
  void keep_zone_state(const FemState& state);

 private:
  bool written_this_run(const std::filesystem::path& file) const;

  const FemPlan& plan_;
  const FemModel& model_;
  const Logger& log_;
  std::optional<FemHistory> history_;
  std::optional<VtkSeries> vtk_;
  std::unique_ptr<Recorders> recorders_;
  std::vector<std::filesystem::path> written_;
  bool zone_exited_ = false;
  std::optional<FemState> zone_state_;
};

class ExplicitStage final : public run::Stage {
 public:
  /// The stage's state (the rest state, or the restart's), its solver and step, and the
  /// motion: everything that can refuse the input is checked here, before any file.
  ExplicitStage(const FemPlan& plan, const FemModel& model, const Logger& log);

  double time() const override { return state_.time; }
  std::int64_t step() const override { return state_.step; }
  void open_outputs(bool resume) override;
  run::StartOutput start() override;
  bool advance_to(double stop) override;
  std::optional<std::string> check_stability() override;
  void write_output(const run::OutputStep& step) override;
  void finish() override;
  run::Work work() const override;
  run::OutputSizes output_sizes() const override;

  /// What the run found (zone, inversion, KE peak from the whole history), with
  /// fem_summary.txt written.
  FemRunSummary summary(const run::RunResult& result) const;

 private:
  /// The shaking (docs/method.md §8): the processed motion and its boundaries.
  struct Shaking {
    std::optional<GroundMotion> motion;
    SeismicBoundary boundary;
  };
  /// The instability guard's references and PE_0.
  struct Guard {
    double pe0 = 0.0;
    GuardLimits limits;
    bool on = false;  ///< from the start of the failure stage
  };
  /// The measures of the current state at an output step, once for the guard and the row.
  struct Measures {
    double time = -1.0;
    std::int64_t step = -1;
    std::vector<Vec2> coordinates;
    std::vector<Vec2> synchronised;  ///< the velocity at the state's time
    ElementGeometry current_geometry;
    Energies energies;
  };

  void make_solver();
  void choose_time_step(bool announce);
  std::string small_step_reason(bool fluid_binds, double damping_reduction) const;
  double step_for(const FemState& state);
  void run_geostatic_stage();
  /// The pore water of a saturated model, for the log (fem/pore_fluid.hpp).
  void log_pore_water() const;
  run::StartOutput start_failure_stage();
  void start_shaking(bool from_geostatic_state);
  void make_recorders();
  void start_recorders(bool resume);
  void set_guard_limits(bool fresh_stage);
  const Measures& measure();
  const ElementGeometry& energy_geometry(Measures& m);
  double total_energy(const Energies& energies) const;
  HistoryRow history_row(const ElementQuality& quality);
  void report_inversion(const HistoryRow& row, const ElementQuality& quality);
  void stop_at_inversion(Index element, double failing_time);
  FemRecord record_of(const FemState& state, const char* stage);
  void write_checkpoint(const FemState& state, const char* stage,
                        const std::filesystem::path& file);
  Vec2 mean_base_displacement(const FemState& state) const;
  BoundaryTable failure_boundaries() const;

  const FemPlan& plan_;
  const FemModel& model_;
  const Logger& log_;
  FemState state_;
  std::optional<ExplicitSolver> solver_;
  double time_step_ = 0.0;  ///< fixed, or the Courant step (small strain: constant)
  double last_step_ = 0.0;  ///< length of the step that led to the current state
  Index steps_ = 0;         ///< steps this run took
  Shaking shaking_;
  Guard guard_;
  FemOutputs outputs_;
  std::optional<Progress> progress_;
  Measures measures_;
};

}  // namespace slide::fem
