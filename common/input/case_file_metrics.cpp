// The case reader's [metrics] table: what the runout measures are relative to.
// Section, the ranges and the shared readers are in case_file_reader.hpp.
#include "common/input/case_file_reader.hpp"

namespace slide::case_reader {

MetricsSpec read_metrics(const Section& root) {
  const Section s =
      root.table("metrics", Section::Keys{"initial_length", "initial_height", "bin_width",
                                          "profile_percentile", "foundation_level"});
  MetricsSpec metrics;
  metrics.initial_length = s.number("initial_length", positive("m"));
  metrics.initial_height = s.number("initial_height", positive("m"));
  metrics.bin_width = s.number("bin_width", positive("m"), metrics.bin_width);
  metrics.profile_percentile =
      s.number("profile_percentile", Range{.min = 0.0, .max = 100.0, .max_closed = true},
               metrics.profile_percentile);
  metrics.foundation_level = s.number("foundation_level", non_negative("m"), 0.0);
  return metrics;
}

}  // namespace slide::case_reader
