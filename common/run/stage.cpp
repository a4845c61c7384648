#include "common/run/stage.hpp"

#include <algorithm>

#include <fmt/format.h>

#include "common/base/error.hpp"
#include "common/io/atomic_file.hpp"

namespace slide::run {

bool drive(Stage& stage, const OutputSchedule& schedule, bool checkpoint_at_end) {
  while (!schedule.is_end(stage.time())) {
    const double stop = schedule.next_stop(stage.time());
    const bool reached = stage.advance_to(stop);
    const double now = stage.time();
    stage.write_output(schedule.is_checkpoint(now) || (checkpoint_at_end && schedule.is_end(now)));
    if (!reached) return false;
  }
  return true;
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
  const std::size_t removed =
      remove_stale_temporaries(output_dir) + remove_stale_temporaries(output_dir / "vtk");
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
