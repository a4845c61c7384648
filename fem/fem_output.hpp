// What fem-solve writes (docs/contract.md): kind "fem" checkpoints, fem_history.csv and the
// VTK series for ParaView. Every file is written atomically (temporary name, rename).
#pragma once

#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include "common/base/log.hpp"
#include "common/io/checkpoint.hpp"
#include "common/io/vtk_output.hpp"
#include "common/run/history_csv.hpp"
#include "fem/fem_model.hpp"
#include "fem/mesh_quality.hpp"

namespace slide::fem {

/// What a checkpoint needs besides the model and the state.
struct CheckpointContext {
  std::string case_name;
  double pe0 = 0.0;                                    ///< J/m
  std::vector<BoundaryCondition> boundary_conditions;  ///< per node set, mesh order
  double friction_coefficient = 0.0;
  SolverSettings solver;  ///< stage, kinematics, energy reference, …
};

FemCheckpoint make_checkpoint(const FemModel& model, const FemState& state,
                              const CheckpointContext& context);

/// The state a checkpoint holds, checked against the model built from its mesh; Error
/// naming `file` and the field on any mismatch. The yield flags are not stored and
/// come back as zero.
FemState state_from_checkpoint(const FemModel& model, const FemCheckpoint& checkpoint,
                               const std::filesystem::path& file);

/// One row of fem_history.csv (docs/contract.md): one per output step.
struct HistoryRow {
  double time = 0.0;
  double kinetic_energy = 0.0;
  double pe0 = 0.0;
  double ke_over_pe0 = 0.0;
  double jacobian_ratio_min = 1.0;
  double jacobian_ratio_avg = 0.0;  ///< NaN ("nan") without elements above εq = 3 %
  double eps_q_avg = 0.0;           ///< NaN ("nan") without elements above εq = 3 %
  double eps_q_max = 0.0;
  Index n_elements_yielding = 0;
  double area_ratio = 1.0;           ///< Σ V_t / Σ V_0
  double scaled_jacobian_min = 1.0;  ///< ≤ 0: an element is inverted (is_inverted)
  double scaled_jacobian_avg = 0.0;  ///< NaN ("nan") without elements above εq = 3 %
  /// Saturated models only (the history's last two columns): the largest pore-pressure
  /// ratio r_u of the Gauss points, and the area of the elements whose mean r_u is at
  /// least high_pore_pressure_ratio, m² (per m, reference areas).
  double pore_pressure_ratio_max = std::numeric_limits<double>::quiet_NaN();
  double high_pore_pressure_area = std::numeric_limits<double>::quiet_NaN();

  /// Inside the recommended transfer zone (NaN averages count as inside).
  bool inside_zone() const;
  /// An element is inverted (is_inverted, det J < 0 at a corner): scaled_jacobian_min < 0.
  /// A row of an older history without that column (NaN) answers as that history's runs
  /// reported inversion, by (|J_t|/|J_0|)_min < 0.
  bool inverted() const;
};

/// fem_history.csv, one HistoryRow per output step (common/run/history_csv.hpp: written
/// whole and atomically after every row, so that a stopped run leaves a complete file).
class FemHistory {
 public:
  /// `water`: a saturated model's history, with the pore-pressure columns.
  FemHistory(std::filesystem::path path, bool water);
  /// On restart: keeps the rows of an existing file up to `time`; a missing or foreign
  /// file starts an empty history (with a warning). A history written before the area
  /// and shape columns existed is kept, those columns NaN.
  void resume(double time, const Logger& logger);
  void add(const HistoryRow& row);
  const std::vector<HistoryRow>& rows() const { return rows_; }

 private:
  bool water_;
  run::HistoryCsv csv_;
  std::vector<HistoryRow> rows_;
};

/// The columns of fem_history.csv (docs/contract.md), in the order of HistoryRow.
inline const std::vector<std::string> history_columns{
    "time",        "kinetic_energy",      "pe0",
    "ke_over_pe0", "jacobian_ratio_min",  "jacobian_ratio_avg",
    "eps_q_avg",   "eps_q_max",           "n_elements_yielding",
    "area_ratio",  "scaled_jacobian_min", "scaled_jacobian_avg"};
/// The columns a saturated model's history adds (docs/contract.md).
inline const std::vector<std::string> pore_water_history_columns{"pore_pressure_ratio_max",
                                                                 "high_pore_pressure_area"};
/// The r_u from which an element counts in high_pore_pressure_area: the liquefaction
/// criterion of docs/method.md §10.
inline constexpr double high_pore_pressure_ratio = 0.7;

/// OUT/vtk/fem_<step>.vtu (the mesh on the current coordinates) and
/// OUT/vtk/fem_gauss_points_<step>.vtu (the Gauss points as a point cloud), collected in
/// OUT/fem.pvd and OUT/fem_gauss_points.pvd.
class VtkSeries {
 public:
  explicit VtkSeries(const std::filesystem::path& output_dir);
  void resume(double time);
  void write(const FemModel& model, const FemState& state, std::span<const Vec2> coordinates,
             const ElementQuality& quality);

 private:
  std::filesystem::path folder_;
  PvdCollection mesh_series_;
  PvdCollection gauss_series_;
};

}  // namespace slide::fem
