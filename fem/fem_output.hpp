// What fem-solve writes (CONTRACT.md): kind "fem" checkpoints, fem_history.csv and the
// VTK series for ParaView. Every file is written atomically (temporary name, rename).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "common/checkpoint.hpp"
#include "common/log.hpp"
#include "common/vtk_output.hpp"
#include "fem/fem_model.hpp"
#include "fem/mesh_quality.hpp"

namespace slide::fem {

/// "fem_t2.000.h5": the checkpoint file name of time t (three decimals).
std::string checkpoint_file_name(double time);

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

/// One row of fem_history.csv (CONTRACT.md): one per output step.
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

  /// Inside the recommended transfer zone (NaN averages count as inside).
  bool inside_zone() const;
  /// An element is inverted (is_inverted, det J < 0 at a corner): scaled_jacobian_min < 0.
  /// A row of an older history without that column (NaN) answers as that history's runs
  /// reported inversion, by (|J_t|/|J_0|)_min < 0.
  bool inverted() const;
};

/// fem_history.csv, rewritten atomically after every row so that a stopped run leaves
/// a complete file.
class HistoryFile {
 public:
  explicit HistoryFile(std::filesystem::path path) : path_(std::move(path)) {}
  /// On restart: keeps the rows of an existing file up to `time`; a missing or foreign
  /// file starts an empty history (with a warning). A history written before the area
  /// and shape columns existed (history_header_without_shape) is kept, those columns NaN.
  void resume(double time, const Logger& logger);
  void add(const HistoryRow& row);
  const std::vector<HistoryRow>& rows() const { return rows_; }

 private:
  void write() const;
  std::filesystem::path path_;
  std::vector<HistoryRow> rows_;
};

inline constexpr const char* history_header =
    "time,kinetic_energy,pe0,ke_over_pe0,jacobian_ratio_min,jacobian_ratio_avg,eps_q_avg,"
    "eps_q_max,n_elements_yielding,area_ratio,scaled_jacobian_min,scaled_jacobian_avg";
/// The header of the histories fem-solve wrote before area_ratio and the scaled Jacobian.
inline constexpr const char* history_header_without_shape =
    "time,kinetic_energy,pe0,ke_over_pe0,jacobian_ratio_min,jacobian_ratio_avg,eps_q_avg,"
    "eps_q_max,n_elements_yielding";

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
