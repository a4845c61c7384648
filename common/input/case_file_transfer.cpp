// The case reader's [transfer] table: the particles and interpolation of fem2mpm.
// Section, the ranges and the shared readers are in case_file_reader.hpp.
#include "common/geometry/triangle_rules.hpp"
#include "common/input/case_file_reader.hpp"

namespace slide::case_reader {

TransferSpec read_transfer(const Section& root, const FemSpec& fem) {
  TransferSpec transfer;
  const auto s = root.optional_table(
      "transfer",
      Section::Keys{"particles_per_element", "particles_per_triangle", "stress_interpolation",
                    "rbf_polynomial", "rbf_shape", "rbf_neighbours", "sweep_times", "main_time"});
  if (!s) return transfer;  // every key has a default
  std::tie(transfer.particles_x, transfer.particles_y) =
      read_particle_layout(*s, "particles_per_element", transfer.particles_x);
  if (s->has("particles_per_triangle")) {
    const int n = s->integer("particles_per_triangle", 1, std::numeric_limits<int>::max(),
                             transfer.particles_triangle);
    // The transfer's own rule, so that the case file accepts what fem2mpm does.
    if (!has_triangle_rule(n)) {
      s->reader().inadmissible(s->node("particles_per_triangle"),
                               s->dotted("particles_per_triangle"), fmt::format("{}", n),
                               supported_triangle_counts());
    }
    transfer.particles_triangle = n;
  }
  transfer.stress_interpolation = s->choice("stress_interpolation", interpolation_names,
                                            std::optional(StressInterpolation::rbf));
  if (s->has("rbf_polynomial")) {
    transfer.rbf_polynomial =
        s->choice("rbf_polynomial", polynomial_names, std::optional<RbfPolynomial>());
  }
  transfer.rbf_shape = s->number("rbf_shape", non_negative("m"), 0.0);
  transfer.rbf_neighbours =
      s->integer("rbf_neighbours", 0, std::numeric_limits<int>::max(), transfer.rbf_neighbours);
  // A transfer needs an FE state: t_T lies within the FE run (t_T = 0: the geostatic
  // state).
  const Range fe_times{.min = 0.0,
                       .min_closed = true,
                       .max = fem.end_time,
                       .max_closed = true,
                       .unit = "s",
                       .note = "within fem.end_time"};
  transfer.sweep_times = s->numbers("sweep_times", fe_times, true);
  transfer.main_time = s->number("main_time", fe_times, 0.0);
  return transfer;
}

}  // namespace slide::case_reader
