// The measurements of a transfer-time sweep (docs/method.md §6, docs/contract.md sweep.csv):
// one row per run (tt0, tt1, ..., pure-mpm, pure-fem) with runout, crest height and
// profile RMSE against the tt0 run, the FE mesh quality at the transfer time and,
// after the docs/contract.md columns, the run's KE/PE0 peak, its time and that time over τc,
// then the stress quality at rest of its final state (50th, 90th, 99th percentiles and
// maximum of e_p, common/physics/runout_metrics.hpp).
#pragma once

#include <cmath>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "common/input/case_file.hpp"
#include "common/physics/runout_metrics.hpp"

namespace slide::tools {

/// One row of fem_history.csv.
struct FemHistoryRow {
  double time = 0.0;
  double kinetic_energy = 0.0, pe0 = 0.0, ke_over_pe0 = 0.0;
  double jacobian_ratio_min = 0.0, jacobian_ratio_avg = 0.0;
  double eps_q_avg = 0.0, eps_q_max = 0.0;
  double n_elements_yielding = 0.0;
  // The area and shape columns: NaN when the history predates them.
  double area_ratio = std::nan("");
  double scaled_jacobian_min = std::nan("");  ///< ≤ 0: an element is inverted
  double scaled_jacobian_avg = std::nan("");
};

/// Reads fem_history.csv (docs/contract.md columns, by name; area_ratio, scaled_jacobian_min
/// and scaled_jacobian_avg may be missing, as in histories written before them, and are
/// then NaN); throws Error naming the file.
std::vector<FemHistoryRow> read_fem_history(const std::filesystem::path& path);

/// One (time, KE/PE0) sample of an FE or MPM history.
struct EnergySample {
  double time = 0.0;
  double ke_over_pe0 = 0.0;
};

/// Reads the `time` and `ke_over_pe0` columns (by name) of fem_history.csv or
/// mpm_history.csv; throws Error naming the file, line and problem.
std::vector<EnergySample> read_energy_history(const std::filesystem::path& path);

/// The samples of a hybrid run transferred at `tt`: the FE history up to t_T, then the
/// MPM history (which starts at t_T).
std::vector<EnergySample> transfer_run_energy(const std::vector<FemHistoryRow>& fem, double tt,
                                              const std::vector<EnergySample>& mpm);

struct EnergyPeak {
  double ke_over_pe0 = 0.0;
  double time = 0.0;  ///< s, of the first sample with the largest value
};

/// The largest finite KE/PE0 of the samples (the earliest on ties); none if no sample is
/// finite.
std::optional<EnergyPeak> ke_over_pe0_peak(const std::vector<EnergySample>& samples);

/// The row at `time` (within 1e-6 s), if any.
std::optional<FemHistoryRow> history_at(const std::vector<FemHistoryRow>& history, double time);

/// Transfer times of the sweep: the case's sweep_times within the FE end time, for as
/// long as the mesh has not entangled: (|J_t|/|J_0|)_min > 0 and no element inverted
/// (scaled_jacobian_min > 0, the definition fem2mpm refuses by; not checked for a
/// history without that column) at that time.
std::vector<double> valid_transfer_times(const Case& c, const std::vector<FemHistoryRow>& history);

struct RunMetrics {
  std::string run;           ///< "tt2", "pure-mpm", "pure-fem"
  std::optional<double> tt;  ///< transfer time, s (none for pure runs)
  SurfaceProfile profile;
  RunoutMeasures measures;
  FrontMeasures front;  ///< the front of 95 % of the mass and the sheet beyond it
  std::optional<FemHistoryRow> fem_at_transfer;
  std::optional<EnergyPeak> ke_peak;  ///< over the whole run (FE phase included)
  StressQuality stress_quality;       ///< of the final particles (NaN: none at rest)
};

/// Measures the final particles of one run (a "particles" or "mpm" checkpoint): the
/// profile, the runout measures and the stress quality at rest (H0 =
/// metrics.initial_height, the foundation level of the profile, ρ of each particle's
/// material from the file's /materials).
RunMetrics measure_run(const Case& c, const std::string& run, std::optional<double> tt,
                       const std::filesystem::path& particle_file);

/// Writes sweep.csv (docs/contract.md columns, then ke_over_pe0_peak, ke_over_pe0_peak_time,
/// ke_over_pe0_peak_time_over_tauc, stress_quality_p50, stress_quality_p90,
/// stress_quality_p99, stress_quality_max, x_toe, x_front_95, sheet_length,
/// sheet_mass_share, sheet_thickness) with errors and RMSE against the run called
/// `reference` (normally "tt0"); empty cells where a value is not defined (the stress
/// quality of a run without particles at rest).
std::string sweep_csv(const Case& c, const std::vector<RunMetrics>& runs,
                      const std::string& reference);
/// The same table in Markdown, for the report.
std::string sweep_markdown(const Case& c, const std::vector<RunMetrics>& runs,
                           const std::string& reference);

/// The surface profiles of all runs, long format: run, bin, x_centre, height.
std::string profiles_csv(const std::vector<RunMetrics>& runs);

/// Initial particle spacing p of the case (MPM cell size / particles per cell).
double particle_spacing(const Case& c);
/// Critical time τc = sqrt(H0 / g).
double critical_time(const Case& c);

}  // namespace slide::tools
