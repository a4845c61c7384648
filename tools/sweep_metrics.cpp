#include "tools/sweep_metrics.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string_view>

#include <fmt/format.h>

#include "common/base/error.hpp"
#include "common/io/checkpoint.hpp"
#include "common/run/history_csv.hpp"

namespace slide::tools {

namespace {

/// "-0", "-0.0 %" and the like: a value that rounds to zero is printed without a minus
/// sign ("+" kept where the format asks for a sign).
std::string without_negative_zero(std::string text, bool signed_format) {
  if (text.empty() || text[0] != '-') return text;
  if (text.find_first_of("123456789") != std::string::npos) return text;
  if (signed_format) {
    text[0] = '+';
  } else {
    text.erase(0, 1);
  }
  return text;
}

std::string cell(std::optional<double> value, const char* format = "{:.6g}") {
  if (!value || !std::isfinite(*value)) return "";
  const std::string text = fmt::format(fmt::runtime(format), *value);
  return without_negative_zero(text, std::string_view(format).find('+') != std::string_view::npos);
}

const RunMetrics* find_run(const std::vector<RunMetrics>& runs, const std::string& name) {
  for (const auto& run : runs) {
    if (run.run == name) return &run;
  }
  return nullptr;
}

/// The derived quantities of one row, shared by the CSV and Markdown writers.
struct SweepRow {
  std::optional<double> tt, tt_over_tauc, runout, runout_normalised, runout_normalised_error,
      crest_height, crest_height_error, rmse, jacobian_ratio_min, jacobian_ratio_avg, eps_q_avg,
      ke_over_pe0_peak, ke_over_pe0_peak_time, ke_over_pe0_peak_time_over_tauc, stress_quality_p50,
      stress_quality_p90, stress_quality_p99, stress_quality_max, x_toe, x_front, sheet_length,
      sheet_mass_share, sheet_thickness;
};

SweepRow sweep_row(const Case& c, const RunMetrics& run, const RunMetrics* reference) {
  SweepRow row;
  row.tt = run.tt;
  if (run.tt) row.tt_over_tauc = *run.tt / critical_time(c);
  row.runout = run.measures.runout;
  row.runout_normalised = run.measures.runout_normalised;
  row.crest_height = run.measures.crest_height;
  row.x_toe = run.measures.x_toe;
  row.x_front = run.front.x_front;
  row.sheet_length = run.front.sheet_length;
  row.sheet_mass_share = run.front.sheet_mass_share;
  row.sheet_thickness = run.front.sheet_thickness;
  if (reference != nullptr) {
    const auto& ref = reference->measures;
    // A relative error of a runout the profile does not resolve says nothing (−102 % of a
    // 0.1 m toe advance on 2 m bins): below one bin the cell stays empty and the runout
    // column (m) carries the comparison.
    if (std::abs(ref.runout) >= c.metrics.bin_width) {
      row.runout_normalised_error =
          (run.measures.runout_normalised - ref.runout_normalised) / ref.runout_normalised;
    }
    row.crest_height_error = (run.measures.crest_height - ref.crest_height) / ref.crest_height;
    row.rmse = profile_rmse(run.profile, reference->profile, particle_spacing(c));
  }
  if (run.fem_at_transfer) {
    row.jacobian_ratio_min = run.fem_at_transfer->jacobian_ratio_min;
    row.jacobian_ratio_avg = run.fem_at_transfer->jacobian_ratio_avg;
    row.eps_q_avg = run.fem_at_transfer->eps_q_avg;
  }
  if (run.ke_peak) {
    row.ke_over_pe0_peak = run.ke_peak->ke_over_pe0;
    row.ke_over_pe0_peak_time = run.ke_peak->time;
    row.ke_over_pe0_peak_time_over_tauc = run.ke_peak->time / critical_time(c);
  }
  // NaN without a deposit: `cell` leaves those empty.
  row.stress_quality_p50 = run.stress_quality.p50;
  row.stress_quality_p90 = run.stress_quality.p90;
  row.stress_quality_p99 = run.stress_quality.p99;
  row.stress_quality_max = run.stress_quality.max;
  return row;
}

}  // namespace

std::vector<FemHistoryRow> read_fem_history(const std::filesystem::path& path) {
  const std::vector<std::pair<std::string, double FemHistoryRow::*>> fields{
      {"time", &FemHistoryRow::time},
      {"kinetic_energy", &FemHistoryRow::kinetic_energy},
      {"pe0", &FemHistoryRow::pe0},
      {"ke_over_pe0", &FemHistoryRow::ke_over_pe0},
      {"jacobian_ratio_min", &FemHistoryRow::jacobian_ratio_min},
      {"jacobian_ratio_avg", &FemHistoryRow::jacobian_ratio_avg},
      {"eps_q_avg", &FemHistoryRow::eps_q_avg},
      {"eps_q_max", &FemHistoryRow::eps_q_max},
      {"n_elements_yielding", &FemHistoryRow::n_elements_yielding},
      // Optional from here on (read_fem_history in sweep_metrics.hpp).
      {"area_ratio", &FemHistoryRow::area_ratio},
      {"scaled_jacobian_min", &FemHistoryRow::scaled_jacobian_min},
      {"scaled_jacobian_avg", &FemHistoryRow::scaled_jacobian_avg}};
  const std::size_t required = 9;
  std::vector<std::string> names, optional;
  for (std::size_t i = 0; i < fields.size(); ++i) {
    (i < required ? names : optional).push_back(fields[i].first);
  }
  std::vector<FemHistoryRow> rows;
  for (const auto& values : run::read_history(path, "the FE history", names, optional)) {
    FemHistoryRow row;
    for (std::size_t i = 0; i < fields.size(); ++i) row.*fields[i].second = values[i];
    rows.push_back(row);
  }
  return rows;
}

std::vector<EnergySample> read_energy_history(const std::filesystem::path& path) {
  std::vector<EnergySample> samples;
  for (const auto& values : run::read_history(path, "the history", {"time", "ke_over_pe0"})) {
    samples.push_back({values[0], values[1]});
  }
  return samples;
}

std::vector<EnergySample> transfer_run_energy(const std::vector<FemHistoryRow>& fem, double tt,
                                              const std::vector<EnergySample>& mpm) {
  std::vector<EnergySample> samples;
  for (const auto& row : fem) {
    if (row.time <= tt + 1e-6) samples.push_back({row.time, row.ke_over_pe0});
  }
  samples.insert(samples.end(), mpm.begin(), mpm.end());
  return samples;
}

std::optional<EnergyPeak> ke_over_pe0_peak(const std::vector<EnergySample>& samples) {
  std::optional<EnergyPeak> peak;
  for (const auto& sample : samples) {
    if (!std::isfinite(sample.ke_over_pe0)) continue;
    if (!peak || sample.ke_over_pe0 > peak->ke_over_pe0) peak = {sample.ke_over_pe0, sample.time};
  }
  return peak;
}

std::optional<FemHistoryRow> history_at(const std::vector<FemHistoryRow>& history, double time) {
  for (const auto& row : history) {
    if (std::abs(row.time - time) < 1e-6) return row;
  }
  return std::nullopt;
}

std::vector<double> valid_transfer_times(const Case& c, const std::vector<FemHistoryRow>& history) {
  std::vector<double> times;
  for (double t : c.transfer.sweep_times) {
    if (t > c.fem.end_time + 1e-9) break;
    const auto row = history_at(history, t);
    if (!row || !(row->jacobian_ratio_min > 0.0) || row->scaled_jacobian_min < 0.0) break;
    times.push_back(t);
  }
  return times;
}

double particle_spacing(const Case& c) {
  return c.mpm.cell_size / c.mpm.particles_x;
}

double critical_time(const Case& c) {
  return std::sqrt(c.metrics.initial_height / gravity_acceleration);
}

RunMetrics measure_run(const Case& c, const std::string& run, std::optional<double> tt,
                       const std::filesystem::path& particle_file) {
  ParticleCheckpoint checkpoint = read_particle_checkpoint(particle_file);
  Particles& p = checkpoint.particles;
  // A shaken run: positions from the base, which the MPM grid followed (docs/method.md §8).
  if (checkpoint.motion) {
    const Vec2 shift =
        base_position(*checkpoint.motion, grid_motion(*checkpoint.motion), checkpoint.header.time);
    for (Vec2& x : p.coordinates) x -= shift;
  }
  RunMetrics metrics;
  metrics.run = run;
  metrics.tt = tt;
  metrics.profile = surface_profile(p.coordinates, c.metrics.bin_width,
                                    c.metrics.profile_percentile, c.metrics.foundation_level);
  metrics.measures = runout_measures(metrics.profile, c.metrics.initial_length);
  // σyy and ρ of every particle; the file's own material table (validated on read, so
  // every material_id indexes it).
  std::vector<double> sigma_yy(p.count()), density(p.count());
  for (std::size_t i = 0; i < p.count(); ++i) {
    sigma_yy[i] = p.stress[i][1];
    density[i] = checkpoint.materials[static_cast<std::size_t>(p.material_id[i])].density;
  }
  metrics.front =
      front_measures(p.coordinates, p.mass, p.volume, metrics.profile, c.metrics.foundation_level);
  metrics.stress_quality =
      stress_quality_at_rest(p.coordinates, p.velocity, sigma_yy, density, metrics.profile,
                             c.metrics.initial_height, c.metrics.foundation_level);
  return metrics;
}

std::string sweep_csv(const Case& c, const std::vector<RunMetrics>& runs,
                      const std::string& reference) {
  const RunMetrics* ref = find_run(runs, reference);
  std::string csv =
      "run,tt,tt_over_tauc,runout,runout_normalised,runout_normalised_error,crest_height,"
      "crest_height_error,rmse,jacobian_ratio_min,jacobian_ratio_avg,eps_q_avg,"
      "ke_over_pe0_peak,ke_over_pe0_peak_time,ke_over_pe0_peak_time_over_tauc,"
      "stress_quality_p50,stress_quality_p90,stress_quality_p99,stress_quality_max,"
      "x_toe,x_front_95,sheet_length,sheet_mass_share,sheet_thickness\n";
  for (const auto& run : runs) {
    const SweepRow r = sweep_row(c, run, ref);
    csv += fmt::format("{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}\n",
                       run.run, cell(r.tt), cell(r.tt_over_tauc), cell(r.runout),
                       cell(r.runout_normalised), cell(r.runout_normalised_error),
                       cell(r.crest_height), cell(r.crest_height_error), cell(r.rmse),
                       cell(r.jacobian_ratio_min), cell(r.jacobian_ratio_avg), cell(r.eps_q_avg),
                       cell(r.ke_over_pe0_peak), cell(r.ke_over_pe0_peak_time),
                       cell(r.ke_over_pe0_peak_time_over_tauc), cell(r.stress_quality_p50),
                       cell(r.stress_quality_p90), cell(r.stress_quality_p99),
                       cell(r.stress_quality_max), cell(r.x_toe), cell(r.x_front),
                       cell(r.sheet_length), cell(r.sheet_mass_share), cell(r.sheet_thickness));
  }
  return csv;
}

std::string profiles_csv(const std::vector<RunMetrics>& runs) {
  std::string csv = "run,bin,x_centre,height\n";
  for (const auto& run : runs) {
    const double w = run.profile.bin_width;
    for (std::size_t b = 0; b < run.profile.height.size(); ++b) {
      csv += fmt::format("{},{},{:.6g},{:.6g}\n", run.run, b, (static_cast<double>(b) + 0.5) * w,
                         run.profile.height[b]);
    }
  }
  return csv;
}

std::string sweep_markdown(const Case& c, const std::vector<RunMetrics>& runs,
                           const std::string& reference) {
  const RunMetrics* ref = find_run(runs, reference);
  // A "|" inside a cell must be escaped, or Markdown starts a new cell there.
  std::string md =
      "| run | t_T (s) | t_T/τc | R (m) | R_N | R_N error | H_c (m) | H_c error | RMSE | "
      "(\\|J_t\\|/\\|J_0\\|)_min | (\\|J_t\\|/\\|J_0\\|)_avg | εq,avg | KE/PE0 peak | "
      "peak t (s) | peak t/τc | e p50 | e p90 | e p99 | e max | x_toe (m) | x_95 (m) | "
      "sheet: length (m), mass, thickness (m) |\n"
      "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  auto percent = [](std::optional<double> v) { return v ? cell(*v * 100.0, "{:+.1f} %") : ""; };
  for (const auto& run : runs) {
    const SweepRow r = sweep_row(c, run, ref);
    md += fmt::format(
        "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} "
        "| {} | {} | {} | {} |\n",
        run.run, cell(r.tt, "{:.3g}"), cell(r.tt_over_tauc, "{:.2f}"), cell(r.runout, "{:.2f}"),
        cell(r.runout_normalised, "{:.3f}"), percent(r.runout_normalised_error),
        cell(r.crest_height, "{:.2f}"), percent(r.crest_height_error), cell(r.rmse, "{:.3f}"),
        cell(r.jacobian_ratio_min, "{:.3f}"), cell(r.jacobian_ratio_avg, "{:.3f}"),
        r.eps_q_avg ? cell(*r.eps_q_avg * 100.0, "{:.1f} %") : "",
        cell(r.ke_over_pe0_peak, "{:.3g}"), cell(r.ke_over_pe0_peak_time, "{:.2f}"),
        cell(r.ke_over_pe0_peak_time_over_tauc, "{:.2f}"), cell(r.stress_quality_p50, "{:#.3g}"),
        cell(r.stress_quality_p90, "{:#.3g}"), cell(r.stress_quality_p99, "{:#.3g}"),
        cell(r.stress_quality_max, "{:#.3g}"), cell(r.x_toe, "{:.2f}"), cell(r.x_front, "{:.2f}"),
        r.sheet_length
            ? fmt::format("{:.2f}, {:.1f} %, {:.2f}", *r.sheet_length,
                          100.0 * r.sheet_mass_share.value_or(0.0), r.sheet_thickness.value_or(0.0))
            : "");
  }
  return md;
}

}  // namespace slide::tools
