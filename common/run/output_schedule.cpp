#include "common/run/output_schedule.hpp"

#include <fmt/format.h>

#include "common/base/error.hpp"
#include "common/base/numeric.hpp"

namespace slide::run {

namespace {

/// The first grid time k·Δ strictly after t (beyond the tolerance).
double next_on_grid(double time, double every) {
  const double k = std::floor((time + OutputSchedule::tolerance(time)) / every) + 1.0;
  return k * every;
}

}  // namespace

bool OutputSchedule::on_grid(double time, double every) {
  if (!(every > 0.0)) return false;
  const double k = std::round(time / every);
  return std::abs(time - k * every) <= tolerance(time);
}

OutputSchedule::OutputSchedule(double end_time, double output_every,
                               std::vector<double> checkpoint_every,
                               std::vector<double> checkpoint_times)
    : end_time_(end_time), output_every_(output_every) {
  for (double every : checkpoint_every) {
    if (every > 0.0) checkpoint_every_.push_back(every);
  }
  for (double t : checkpoint_times) {
    if (t > 0.0 && t <= end_time) checkpoint_times_.push_back(t);
  }
  std::sort(checkpoint_times_.begin(), checkpoint_times_.end());
}

double OutputSchedule::next_stop(double time) const {
  double stop = end_time_;
  const double after = time + tolerance(time);
  if (output_every_ > 0.0) stop = std::min(stop, next_on_grid(time, output_every_));
  for (double every : checkpoint_every_) stop = std::min(stop, next_on_grid(time, every));
  for (double t : checkpoint_times_) {
    if (t > after) {
      stop = std::min(stop, t);
      break;
    }
  }
  // A stop within the tolerance of the end time is the end time.
  return is_end(stop) ? end_time_ : stop;
}

bool OutputSchedule::is_checkpoint(double time) const {
  for (double every : checkpoint_every_) {
    if (on_grid(time, every)) return true;
  }
  return std::any_of(checkpoint_times_.begin(), checkpoint_times_.end(),
                     [&](double t) { return std::abs(time - t) <= tolerance(time); });
}

bool OutputSchedule::is_output(double time) const {
  return on_grid(time, output_every_) || is_checkpoint(time) || is_end(time);
}

double OutputSchedule::checkpoints_after(double time) const {
  const double span = std::max(0.0, end_time_ - time);
  double count = 1.0;  // the end, a checkpoint where the stage checkpoints its end
  for (double every : checkpoint_every_) count += std::floor(span / every) + 1.0;
  for (double t : checkpoint_times_) count += t > time ? 1.0 : 0.0;
  return count;
}

double OutputSchedule::outputs_after(double time) const {
  const double span = std::max(0.0, end_time_ - time);
  const double grid = output_every_ > 0.0 ? std::floor(span / output_every_) + 1.0 : 0.0;
  return grid + checkpoints_after(time);
}

void check_vtk_every(double every, double output_every, std::string_view what) {
  if (!(every > 0.0) || !(output_every > 0.0)) return;
  if (!is_whole_multiple(every, output_every)) {
    throw Error(
        "{} = {} s is not a whole multiple of the output step {} s (frames are written "
        "at output steps)",
        what, every, output_every);
  }
}

double automatic_vtk_every(double start, double end, double output_every) {
  if (!(output_every > 0.0)) return 0.0;
  const double outputs = std::max(0.0, end - start) / output_every;
  const double stride = std::max(1.0, std::ceil(outputs / automatic_vtk_frames - 1e-9));
  return stride * output_every;
}

double choose_vtk_every(std::optional<double> option, std::optional<double> case_value,
                        double start, double end, double output_every) {
  if (option) {
    check_vtk_every(*option, output_every, "--vtk-every");
    return *option;
  }
  return case_value.value_or(automatic_vtk_every(start, end, output_every));
}

std::string describe_vtk_every(double every) {
  return every > 0.0 ? fmt::format("every {:g} s", every) : std::string("at every output step");
}

}  // namespace slide::run
