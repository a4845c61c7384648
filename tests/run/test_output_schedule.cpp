// Where fem-solve stops: output grid, checkpoint cadences and lists, the end time.
#include <gtest/gtest.h>

#include "common/run/output_schedule.hpp"

namespace slide::run {
namespace {

TEST(OutputSchedule, StopsOnTheOutputGridAndTheCheckpointTimes) {
  const OutputSchedule schedule(1.0, 0.1, {0.5}, {0.25});
  std::vector<double> stops;
  for (double t = 0.0; t < 1.0;) {
    t = schedule.next_stop(t);
    stops.push_back(t);
  }
  ASSERT_EQ(stops.size(), 11U);
  EXPECT_DOUBLE_EQ(stops[0], 0.1);
  EXPECT_DOUBLE_EQ(stops[2], 0.25);
  EXPECT_DOUBLE_EQ(stops[3], 0.3);
  EXPECT_EQ(stops.back(), 1.0);
  EXPECT_TRUE(schedule.is_checkpoint(0.25));
  EXPECT_TRUE(schedule.is_checkpoint(5 * 0.1));
  EXPECT_TRUE(schedule.is_checkpoint(1.0));
  EXPECT_FALSE(schedule.is_checkpoint(0.3));
}

TEST(OutputSchedule, GridTimesAreMultiplesNotSums) {
  // 0.1·3 = 0.30000000000000004 in binary; a restart at that time continues with 0.4.
  const OutputSchedule schedule(1.0, 0.1, {}, {});
  EXPECT_EQ(schedule.next_stop(0.1 * 3), 0.1 * 4);
  EXPECT_EQ(schedule.next_stop(0.0), 0.1);
}

TEST(OutputSchedule, TimesWithinTheToleranceAreOneStop) {
  // A listed 0.3 and the grid's 0.30000000000000004 must not make a 5e-17 s step.
  const OutputSchedule schedule(1.0, 0.1, {}, {0.3});
  const double stop = schedule.next_stop(0.2);
  EXPECT_NEAR(stop, 0.3, 1e-15);
  EXPECT_NEAR(schedule.next_stop(stop), 0.4, 1e-15);
  EXPECT_TRUE(schedule.is_checkpoint(0.1 * 3));
}

TEST(OutputSchedule, WithoutOutputCadenceStopsAtCheckpointsOnly) {
  const OutputSchedule schedule(2.0, 0.0, {1.0, 0.0}, {});
  EXPECT_EQ(schedule.next_stop(0.0), 1.0);
  EXPECT_EQ(schedule.next_stop(1.0), 2.0);
  EXPECT_EQ(schedule.next_stop(1.9999999999), 2.0);
}

}  // namespace
}  // namespace slide::run
