#include "common/run/stage.hpp"

#include <algorithm>
#include <chrono>
#include <ctime>
#include <fstream>
#include <limits>
#include <sstream>

#include <fmt/format.h>

#include "common/base/error.hpp"
#include "common/base/program.hpp"
#include "common/io/atomic_file.hpp"
#include "common/run/output_lock.hpp"
#include "common/run/stability_guard.hpp"

namespace slide::run {

/// The outputs of one run: the guard before each, the frame and checkpoint it asks for.
struct Lifecycle {
  Stage& stage;
  const Plan& plan;
  double last_output_time = -std::numeric_limits<double>::infinity();

  /// The output of the current state; `start`: the stage's first, `at_rest`: its last,
  /// before the end time (it came to rest), each a frame whatever the cadence. A time already
  /// written is written again only for a checkpoint.
  void output(bool checkpoint, bool start, bool at_rest = false) {
    const double now = stage.time();
    if (now == last_output_time && !checkpoint) return;
    last_output_time = now;
    if (const auto problem = stage.check_stability()) {
      const std::filesystem::path& last = stage.last_checkpoint();
      throw InstabilityError(
          "instability at t = {:.6g} s (step {}): {}; stopped, the last good checkpoint is {} "
          "(restart from it with a smaller time step or more damping)",
          now, stage.step(), *problem, last.empty() ? "none" : last.string());
    }
    const OutputSchedule& schedule = plan.schedule;
    const bool end_checkpoint = plan.output.checkpoint_at_end && schedule.is_end(now);
    OutputStep step;
    if (checkpoint || end_checkpoint) {
      step.checkpoint =
          plan.output.folder / checkpoint_file_name(plan.output.checkpoint_prefix, now);
    }
    step.frame =
        plan.output.write_vtk &&
        is_vtk_frame(now, plan.output.vtk_every, start || at_rest || !step.checkpoint.empty());
    stage.write_output(step);
    if (!step.checkpoint.empty()) set_last_checkpoint(step.checkpoint);
  }

  void set_last_checkpoint(const std::filesystem::path& file) { stage.last_checkpoint_ = file; }

  /// The loop: every stop of the schedule from the stage's time to the end. False when
  /// the stage came to rest first.
  bool loop() {
    const OutputSchedule& schedule = plan.schedule;
    while (!schedule.is_end(stage.time())) {
      const bool reached = stage.advance_to(schedule.next_stop(stage.time()));
      output(schedule.is_checkpoint(stage.time()), false, !reached);
      if (!reached) return false;
    }
    return true;
  }
};

namespace {

/// run.txt (program, version and commit, start, case and start file) and a copy of each
/// input file in inputs/, each written atomically: what made the folder's outputs (the
/// run's own log goes to <program>.log beside them, Logger::write_to).
void record_provenance(const Plan& plan, const Logger& log) {
  const std::filesystem::path& folder = plan.output.folder;
  std::string inputs;
  for (const auto& input : plan.inputs) {
    std::ifstream in(input, std::ios::binary);
    if (!in)
      throw Error("{}: cannot read it to keep a copy in {}", input.string(), folder.string());
    std::ostringstream text;
    text << in.rdbuf();
    std::filesystem::create_directories(folder / "inputs");
    write_text_atomically(folder / "inputs" / input.filename(), text.str());
    inputs += fmt::format("input = {}\n", std::filesystem::absolute(input).string());
  }
  const auto now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  std::tm utc{};
  gmtime_r(&now, &utc);
  write_text_atomically(
      folder / "run.txt",
      fmt::format(
          "# what made this folder's outputs (docs/contract.md, \"Output files\")\n"
          "program = {}\nversion = {}\ncase = {}\nstart = {}\nstarted_utc = "
          "{:04}-{:02}-{:02}T{:02}:{:02}:{:02}Z\n{}",
          log.program(), version_string(), plan.case_name,
          plan.start_file.empty() ? std::string("the case geometry") : plan.start_file.string(),
          utc.tm_year + 1900, utc.tm_mon + 1, utc.tm_mday, utc.tm_hour, utc.tm_min, utc.tm_sec,
          inputs));
}

}  // namespace

/// The output folder made and locked for this run (the root rank holds the lock), the
/// temporaries of killed runs removed; every rank ends with the root's one-line error.
void prepare_folder(const Plan& plan, const Logger& log, const Ranks& ranks,
                    std::optional<OutputLock>& lock) {
  std::optional<std::string> problem;
  if (ranks.root()) {
    try {
      std::filesystem::create_directories(plan.output.folder);
      lock.emplace(plan.output.folder);
      if (lock->took_over()) {
        log.info("took over the output lock a killed run left in {}", plan.output.folder.string());
      }
      remove_temporaries_of_killed_runs(plan.output.folder, log);
      log.write_to(plan.output.folder / (log.program() + ".log"));
      record_provenance(plan, log);
    } catch (const std::exception& e) {
      problem = e.what();
    }
  }
  // No rank writes before the root has the folder; a refusal ends every rank.
  if (const auto first = ranks.first_problem(problem)) throw Error("{}", *first);
}

/// While a run holds its folder, a rank that ends the job with MPI_Abort (no destructor
/// runs then, the root's lock's included) removes the lock file.
struct LockOnAbort {
  std::string file;
  LockOnAbort(const Plan& plan, const Ranks& ranks)
      : file((plan.output.folder / OutputLock::file_name).string()) {
    if (ranks.distributed()) Ranks::remove_on_abort(file);
  }
  ~LockOnAbort() { Ranks::keep_on_abort(file); }
  LockOnAbort(const LockOnAbort&) = delete;
  LockOnAbort& operator=(const LockOnAbort&) = delete;
};

namespace {

/// The free bytes of the file system that holds `folder` (its nearest existing ancestor
/// when it does not exist yet); infinity when it cannot be told.
double free_bytes(std::filesystem::path folder) {
  std::error_code error;
  folder = std::filesystem::absolute(folder, error);
  while (!folder.empty() && !std::filesystem::exists(folder, error)) {
    if (folder == folder.parent_path()) break;
    folder = folder.parent_path();
  }
  const std::filesystem::space_info space = std::filesystem::space(folder, error);
  if (error) return std::numeric_limits<double>::infinity();
  return static_cast<double>(space.available);
}

}  // namespace

void check_output_volume(const Plan& plan, double time, OutputSizes sizes, const Logger& log,
                         const Ranks& ranks) {
  sizes.checkpoint = ranks.sum(sizes.checkpoint);
  sizes.frame = ranks.sum(sizes.frame);
  std::optional<std::string> problem;
  if (ranks.root()) {
    const OutputSchedule& schedule = plan.schedule;
    const double checkpoints = schedule.checkpoints_after(time);
    const double outputs = schedule.outputs_after(time);
    double frames = 0.0;
    if (plan.output.write_vtk) {
      const double span = std::max(0.0, plan.end_time() - time);
      const double every = plan.output.vtk_every;
      frames =
          every > 0.0 ? std::min(outputs, std::floor(span / every) + 2.0 + checkpoints) : outputs;
    }
    const double bytes = checkpoints * sizes.checkpoint + frames * sizes.frame;
    const double space = free_bytes(plan.output.folder);
    if (checkpoints + frames > max_output_files) {
      problem = fmt::format(
          "the run would write about {:.3g} checkpoints and {:.3g} VTK frames (at most {:.0e} "
          "files): lengthen checkpoint_every, output_every or vtk_every, or pass --no-vtk",
          checkpoints, frames, max_output_files);
    } else if (bytes > space && plan.disk_check) {
      problem = fmt::format(
          "the run would write about {:.3g} GB ({:.3g} checkpoints of {:.3g} MB, {:.3g} VTK "
          "frames of {:.3g} MB) into {}, whose disk has {:.3g} GB free: lengthen the "
          "cadences, pass --no-vtk, free space, or --no-disk-check if the estimate is too "
          "high",
          bytes / 1e9, checkpoints, sizes.checkpoint / 1e6, frames, sizes.frame / 1e6,
          plan.output.folder.string(), space / 1e9);
    }
    if (!problem && bytes > space) {
      // Asked for: said in the log, not as a warning.
      log.info(
          "outputs: about {:.3g} GB into {}, whose disk has {:.3g} GB free (--no-disk-check): "
          "the run may stop on a full disk",
          bytes / 1e9, plan.output.folder.string(), space / 1e9);
    } else if (!problem) {
      log.info(
          "outputs: at most {:.3g} checkpoints of {:.3g} MB and {:.3g} VTK frames of {:.3g} "
          "MB, about {:.3g} GB ({:.3g} GB free)",
          checkpoints, sizes.checkpoint / 1e6, frames, sizes.frame / 1e6, bytes / 1e9, space / 1e9);
    }
  }
  if (const auto first = ranks.first_problem(problem)) throw Error("{}", *first);
}

RunResult execute(Stage& stage, const Plan& plan, const Logger& log, const Ranks& ranks) {
  std::optional<OutputLock> lock;
  check_output_volume(plan, stage.time(), stage.output_sizes(), log, ranks);
  prepare_folder(plan, log, ranks, lock);
  const LockOnAbort lock_on_abort(plan, ranks);
  Lifecycle run{stage, plan};
  if (plan.start == Start::restart) run.set_last_checkpoint(plan.start_file);
  stage.open_outputs(plan.resume_outputs);
  const auto wall_start = std::chrono::steady_clock::now();
  const StartOutput first = stage.start();
  if (first != StartOutput::none) {
    const bool first_output = first == StartOutput::first;
    run.output(first_output && plan.output.checkpoint_at_start &&
                   plan.schedule.is_checkpoint(stage.time()),
               first_output);
  }
  RunResult result;
  result.reached_end = run.loop();
  result.wall_seconds = ranks.max(
      std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count());
  stage.finish();
  result.work = stage.work();
  const double rate =
      result.wall_seconds > 0.0 ? result.work.unit_steps / result.wall_seconds : 0.0;
  log.result("summary: steps={} {}s={} wall_s={:.3f} {}_steps_per_s={:.4g}", result.work.steps,
             result.work.unit, result.work.units, result.wall_seconds, result.work.unit, rate);
  return result;
}

std::string checkpoint_file_name(std::string_view prefix, double time) {
  return fmt::format("{}_t{:.3f}.h5", prefix, time);
}

void check_step_count(double duration, double dt, std::string_view cause) {
  const double steps = duration / dt;
  if (!(steps <= max_steps)) {
    throw Error("the run would take {:.3g} steps of {:.3g} s (at most {:.0e}): {}", steps, dt,
                max_steps, cause);
  }
}

void check_checkpoint_cadence(double every, std::string_view what) {
  if (every > 0.0 && every < checkpoint_name_resolution) {
    throw Error(
        "{} = {} s is finer than the checkpoint names' {} s (checkpoints would replace each "
        "other under one name): use at least {} s",
        what, every, checkpoint_name_resolution, checkpoint_name_resolution);
  }
}

void check_checkpoint_times(std::vector<double> times, std::string_view prefix,
                            std::string_view what, std::vector<double> also) {
  times.insert(times.end(), also.begin(), also.end());
  std::sort(times.begin(), times.end());
  for (std::size_t i = 1; i < times.size(); ++i) {
    const double a = times[i - 1], b = times[i];
    if (b - a > OutputSchedule::tolerance(b) &&
        checkpoint_file_name(prefix, a) == checkpoint_file_name(prefix, b)) {
      throw Error(
          "{}: the checkpoint times {} s and {} s would both be {} (names have three "
          "decimals)",
          what, a, b, checkpoint_file_name(prefix, b));
    }
  }
}

void remove_temporaries_of_killed_runs(const std::filesystem::path& output_dir, const Logger& log) {
  // Every folder a run writes atomically into: the outputs, the VTK frames and the copies
  // of the inputs (record_provenance).
  std::size_t removed = 0;
  for (const char* sub : {"", "vtk", "inputs"})
    removed += remove_stale_temporaries(output_dir / sub);
  if (removed > 0) {
    log.info("removed {} temporary file{} that killed runs left in {}", removed,
             removed == 1 ? "" : "s", output_dir.string());
  }
}

void check_restart_materials(const MaterialTable& from_checkpoint, const MaterialTable& from_case,
                             const std::string& source) {
  if (from_checkpoint.size() != from_case.size()) {
    throw Error("{}: the checkpoint has {} materials, the case {}", source, from_checkpoint.size(),
                from_case.size());
  }
  for (std::size_t i = 0; i < from_case.size(); ++i) {
    const Material& a = from_checkpoint[i];
    const Material& b = from_case[i];
    if (a.name != b.name) {
      throw Error("{}: material {} is \"{}\" in the checkpoint but \"{}\" in the case", source, i,
                  a.name, b.name);
    }
    if (a.density != b.density) {
      throw Error("{}: material \"{}\" has density {} kg/m³ in the checkpoint but {} in the case",
                  source, a.name, a.density, b.density);
    }
  }
}

}  // namespace slide::run
