// Runout measures of METHOD.md §6 on hand-computed particle sets.
#include <cmath>

#include <gtest/gtest.h>

#include "common/runout_metrics.hpp"

namespace slide {
namespace {

TEST(RunoutMetrics, PercentileInterpolatesLinearlyBetweenOrderStatistics) {
  EXPECT_DOUBLE_EQ(percentile({5.0, 1.0, 4.0, 2.0, 3.0}, 99.0), 4.96);
  EXPECT_DOUBLE_EQ(percentile({5.0, 1.0, 4.0, 2.0, 3.0}, 50.0), 3.0);
  EXPECT_DOUBLE_EQ(percentile({7.0}, 99.0), 7.0);
  EXPECT_DOUBLE_EQ(percentile({1.0, 2.0}, 100.0), 2.0);
  EXPECT_TRUE(std::isnan(percentile({}, 99.0)));
}

// Bin 0 holds y = 1, 2, 3; bin 1 holds y = 0.5 at x = 3.5; bin 2 is empty; the particle
// in bin 3 is a stray.
const std::vector<Vec2> sample{{0.5, 1.0}, {1.0, 2.0}, {1.9, 3.0}, {3.5, 0.5}, {6.5, 10.0}};

TEST(RunoutMetrics, ProfileAndToeIgnoreParticlesBeyondAnEmptyBin) {
  const SurfaceProfile profile = surface_profile(sample, 2.0, 99.0);
  ASSERT_EQ(profile.height.size(), 2u);
  EXPECT_DOUBLE_EQ(profile.height[0], 2.98);  // rank 1.98 of {1, 2, 3}
  EXPECT_DOUBLE_EQ(profile.height[1], 0.5);
  EXPECT_DOUBLE_EQ(profile.x_toe, 3.5);
  EXPECT_EQ(profile.stray_count, 1u);
}

TEST(RunoutMetrics, RunoutIsMeasuredFromTheInitialLength) {
  const RunoutMeasures m = runout_measures(surface_profile(sample, 2.0, 99.0), 2.0);
  EXPECT_DOUBLE_EQ(m.x_toe, 3.5);
  EXPECT_DOUBLE_EQ(m.runout, 1.5);
  EXPECT_DOUBLE_EQ(m.runout_normalised, 0.75);
  EXPECT_DOUBLE_EQ(m.crest_height, 2.98);
}

TEST(RunoutMetrics, RmseNormalisesByReferenceHeightPlusParticleSize) {
  SurfaceProfile reference;
  reference.bin_width = 2.0;
  reference.height = {2.0, 1.0, 0.2};
  reference.x_toe = 3.5;  // toe in bin 1: bins 0 and 1 count, bin 2 does not
  SurfaceProfile run;
  run.bin_width = 2.0;
  run.height = {3.0};  // the run stops in bin 0: bin 1 counts as height 0
  run.x_toe = 1.5;
  const double e0 = (3.0 - 2.0) / (2.0 + 0.5), e1 = (0.0 - 1.0) / (1.0 + 0.5);
  EXPECT_DOUBLE_EQ(profile_rmse(run, reference, 0.5), std::sqrt((e0 * e0 + e1 * e1) / 2.0));
  EXPECT_DOUBLE_EQ(profile_rmse(reference, reference, 0.5), 0.0);
}

TEST(RunoutMetrics, FoundationLayerIsLeftOutOfTheProfileAndToe) {
  // A foundation layer (y ≤ 1) reaching x = 9 and debris on it up to x = 3.5.
  std::vector<Vec2> points{{0.5, 3.0}, {1.5, 2.0}, {3.5, 1.5}};
  for (double x = 0.25; x < 9.0; x += 0.5) points.emplace_back(x, 0.75);
  EXPECT_DOUBLE_EQ(surface_profile(points, 2.0).x_toe, 8.75);
  const SurfaceProfile above = surface_profile(points, 2.0, 99.0, 1.0);
  EXPECT_DOUBLE_EQ(above.x_toe, 3.5);
  ASSERT_EQ(above.height.size(), 2u);
  EXPECT_DOUBLE_EQ(above.height[1], 1.5);
}

TEST(RunoutMetrics, ACrestSunkBelowTheFoundationLevelKeepsItsHeightAndTheToe) {
  // Foundation top at y = 1 to x = 9; the crest (bins 0 and 1) has sunk to y = 0.8 and
  // 0.9, and debris above the level lies in bins 2 and 3 (toe 7.5), a stray at 11.5.
  std::vector<Vec2> points{{0.5, 0.8}, {2.5, 0.9}, {4.5, 2.0}, {5.0, 1.6}, {7.5, 1.2}, {11.5, 1.1}};
  for (double x = 0.25; x < 9.0; x += 0.5) points.emplace_back(x, 0.5);
  const SurfaceProfile p = surface_profile(points, 2.0, 50.0, 1.0);
  EXPECT_DOUBLE_EQ(p.x_toe, 7.5);
  EXPECT_EQ(p.stray_count, 1u);
  ASSERT_EQ(p.height.size(), 4u);
  // Bin 0 (x < 2): all its particles, y = 0.8 and 0.5 ×4: median 0.5. Bin 1: the
  // median of 0.9 and 0.5 ×4 is 0.5; with the 99th percentile it is 0.5 + 0.96·0.4.
  EXPECT_DOUBLE_EQ(p.height[0], 0.5);
  EXPECT_DOUBLE_EQ(p.height[2], 1.8);  // median of 2.0 and 1.6 (above the level only)
  EXPECT_DOUBLE_EQ(p.height[3], 1.2);
  EXPECT_NEAR(surface_profile(points, 2.0, 99.0, 1.0).height[1], 0.5 + 0.96 * 0.4, 1e-12);
  const RunoutMeasures m = runout_measures(p, 5.0);
  EXPECT_DOUBLE_EQ(m.runout, 2.5);
  EXPECT_DOUBLE_EQ(m.crest_height, 0.5);
  // Without a foundation level (METHOD.md §6) the run starts at the wall: every bin
  // has particles out to bin 5, and the toe is the stray.
  EXPECT_DOUBLE_EQ(surface_profile(points, 2.0).x_toe, 11.5);
}

}  // namespace
}  // namespace slide
