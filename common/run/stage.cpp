#include "common/run/stage.hpp"

#include <fmt/format.h>

#include "common/base/error.hpp"

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
