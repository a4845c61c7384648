// slide-metrics: measurements for the case pipelines (docs/method.md §6, docs/contract.md).
//
//   slide-metrics case-info CASE.toml             make variables of a case
//   slide-metrics transfer-times CASE.toml FEM_HISTORY.csv
//                                                 the sweep's valid transfer times
//   slide-metrics measure CASE.toml PARTICLES.h5  toe, R, R_N, H_c of one state, and
//                                                 its stress quality at rest
//   slide-metrics sweep CASE.toml OUT/            OUT/sweep.csv and OUT/sweep.md
//
// `sweep` looks in OUT/ for tt<T>/mpm_final.h5, pure-mpm/mpm_final.h5 and
// pure-fem/particles_final.h5, and reads the FE mesh quality at each transfer time
// from OUT/fem/fem_history.csv. Errors and RMSE are against the tt0 run. The KE/PE0
// peak of a run comes from its histories: for tt<T> the FE phase up to T
// (fem/fem_history.csv) and tt<T>/mpm_history.csv, for pure-mpm its mpm_history.csv,
// for pure-fem its fem_history.csv (a missing history leaves the cells empty). The
// stress quality at rest (docs/method.md §6) is that of the same final particle file; for
// pure-fem it is the FE end state carried onto particles element by element (its
// velocities are the FE ones), measured like the MPM deposits. It also
// writes OUT/sweep.md (the table for the report) and OUT/profiles.csv (every run's
// surface profile, for the plots).
#include <algorithm>
#include <filesystem>
#include <tuple>

#include <fmt/format.h>

#include "common/base/error.hpp"
#include "common/base/program.hpp"
#include "common/input/case_file.hpp"
#include "common/io/atomic_file.hpp"
#include "tools/sweep_metrics.hpp"

namespace fs = std::filesystem;
using namespace slide;
using namespace slide::tools;

namespace {

std::string join(const std::vector<double>& values) {
  std::string text;
  for (double v : values) text += fmt::format("{}{:g}", text.empty() ? "" : " ", v);
  return text;
}

void case_info(const fs::path& case_file) {
  const Case c = load_case(case_file);
  fmt::print("NAME={}\n", c.name);
  fmt::print("MAIN_TT={:g}\n", c.transfer.main_time);
  fmt::print("SWEEP_TTS={}\n", join(c.transfer.sweep_times));
  fmt::print("FEM_END={:g}\n", c.fem.failure_stage ? c.fem.end_time : 0.0);
  fmt::print("MPM_END={:g}\n", c.mpm.end_time);
  fmt::print("TAU_C={:.6g}\n", critical_time(c));
  // The mesh file the FE phase reads, when the case has one: a prerequisite of its runs.
  fmt::print("MESH_FILE={}\n", c.mesh.file().string());
  // Every other file the runs read: the base motion's records (a run is stale when one
  // of them is edited).
  std::string files;
  if (c.fem.motion) {
    for (const auto& component : {c.fem.motion->horizontal, c.fem.motion->vertical}) {
      if (component && component->source == MotionSource::file) {
        files += (files.empty() ? "" : " ") + component->file.string();
      }
    }
  }
  fmt::print("CASE_FILES={}\n", files);
}

void transfer_times(const fs::path& case_file, const fs::path& history_file) {
  const Case c = load_case(case_file);
  fmt::print("{}\n", join(valid_transfer_times(c, read_fem_history(history_file))));
}

void measure(const fs::path& case_file, const fs::path& particles) {
  const Case c = load_case(case_file);
  const RunMetrics m = measure_run(c, particles.stem().string(), std::nullopt, particles);
  fmt::print(
      "x_toe={:.4f} runout={:.4f} runout_normalised={:.5f} crest_height={:.4f} "
      "bins={} strays={}\n",
      m.measures.x_toe, m.measures.runout, m.measures.runout_normalised, m.measures.crest_height,
      m.profile.height.size(), m.profile.stray_count);
  // The front of 95 % of the mass and the sheet beyond it (docs/method.md §6).
  fmt::print(
      "front: x_95={:.4f} sheet_length={:.4f} sheet_mass_share={:.4f} "
      "sheet_thickness={:.4f}\n",
      m.front.x_front, m.front.sheet_length, m.front.sheet_mass_share, m.front.sheet_thickness);
  // e_p = |σyy − σyy,lith| / (ρ g H0) over the particles at rest (nan: none at rest).
  const StressQuality& q = m.stress_quality;
  fmt::print("stress_quality: deposit={} p50={:.4g} p90={:.4g} p99={:.4g} max={:.4g}\n",
             q.deposit_count, q.p50, q.p90, q.p99, q.max);
}

void sweep(const fs::path& case_file, const fs::path& out) {
  const Case c = load_case(case_file);
  const auto history_file = out / "fem" / "fem_history.csv";
  std::vector<FemHistoryRow> history;
  if (fs::exists(history_file)) history = read_fem_history(history_file);

  std::vector<std::pair<double, fs::path>> transfers;
  if (fs::is_directory(out)) {
    for (const auto& entry : fs::directory_iterator(out)) {
      const std::string name = entry.path().filename().string();
      if (!entry.is_directory() || !name.starts_with("tt")) continue;
      const auto final_file = entry.path() / "mpm_final.h5";
      if (!fs::exists(final_file)) continue;
      try {
        transfers.emplace_back(std::stod(name.substr(2)), final_file);
      } catch (const std::exception&) {
        continue;  // not a transfer folder
      }
    }
  }
  std::sort(transfers.begin(), transfers.end());
  // The samples of a history file, none if it is missing.
  auto energy = [](const fs::path& file) {
    return fs::exists(file) ? read_energy_history(file) : std::vector<EnergySample>{};
  };
  std::vector<RunMetrics> runs;
  for (const auto& [tt, file] : transfers) {
    RunMetrics run = measure_run(c, file.parent_path().filename().string(), tt, file);
    run.fem_at_transfer = history_at(history, tt);
    run.ke_peak = ke_over_pe0_peak(
        transfer_run_energy(history, tt, energy(file.parent_path() / "mpm_history.csv")));
    runs.push_back(std::move(run));
  }
  for (const auto& [name, file, run_history] :
       {std::tuple{"pure-mpm", out / "pure-mpm" / "mpm_final.h5",
                   out / "pure-mpm" / "mpm_history.csv"},
        std::tuple{"pure-fem", out / "pure-fem" / "particles_final.h5",
                   out / "pure-fem" / "fem_history.csv"}}) {
    if (!fs::exists(file)) continue;
    RunMetrics run = measure_run(c, name, std::nullopt, file);
    run.ke_peak = ke_over_pe0_peak(energy(run_history));
    runs.push_back(std::move(run));
  }
  if (runs.empty()) throw Error("{}: no finished run to measure", out.string());
  const std::string reference = runs.front().run == "tt0" ? "tt0" : "";
  if (reference.empty()) {
    fmt::print(stderr, "slide-metrics: warning: no tt0 run in {}: errors and RMSE left empty\n",
               out.string());
  }
  write_text_atomically(out / "sweep.csv", sweep_csv(c, runs, reference));
  write_text_atomically(out / "sweep.md", sweep_markdown(c, runs, reference));
  write_text_atomically(out / "profiles.csv", profiles_csv(runs));
  fmt::print("slide-metrics: {} runs measured: {}\n", runs.size(), (out / "sweep.csv").string());
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"slide-metrics: surface profiles, runout and sweep tables (docs/method.md §6)",
               "slide-metrics"};
  app.require_subcommand(1);
  std::string case_file, second;
  auto* info = app.add_subcommand("case-info", "print a case's make variables");
  info->add_option("case", case_file, "case.toml")->required();
  auto* times = app.add_subcommand("transfer-times", "print the sweep's valid transfer times");
  times->add_option("case", case_file, "case.toml")->required();
  times->add_option("history", second, "fem_history.csv")->required();
  auto* one = app.add_subcommand("measure", "measure one particle state");
  one->add_option("case", case_file, "case.toml")->required();
  one->add_option("particles", second, "particles or mpm checkpoint")->required();
  auto* all = app.add_subcommand("sweep", "measure every run of a case's output folder");
  all->add_option("case", case_file, "case.toml")->required();
  all->add_option("out", second, "the case's output folder")->required();
  if (auto status = parse_command_line(app, argc, argv)) return *status;
  return run_main("slide-metrics", [&] {
    if (*info) case_info(case_file);
    if (*times) transfer_times(case_file, second);
    if (*one) measure(case_file, second);
    if (*all) sweep(case_file, second);
  });
}
