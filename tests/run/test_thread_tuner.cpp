// ThreadTuner (common/run/thread_tuner.hpp) with a stand-in for /proc/stat: the requested
// count on an idle machine, one thread when other processes hold every core, the count
// back when they leave, a lone reading does not decide, one thread requested is never
// changed, and an unreadable count keeps the requested one. And the real /proc/stat reads.
#include <optional>

#include <gtest/gtest.h>

#include "common/run/thread_tuner.hpp"

namespace slide::run {
namespace {

TEST(ThreadTuner, FollowsTheCoresOtherProcessesLeaveFree) {
  int running = 1;  // this process alone
  ThreadTuner tuner(
      2, 2, [&] { return std::optional<int>(running); }, 10, 4);
  for (int s = 0; s < 100; ++s) tuner.record_step();
  EXPECT_EQ(tuner.threads(), 2);
  running = 3;                                       // a busy process on each core
  for (int s = 0; s < 40; ++s) tuner.record_step();  // four readings
  EXPECT_EQ(tuner.threads(), 1);
  running = 1;
  for (int s = 0; s < 40; ++s) tuner.record_step();
  EXPECT_EQ(tuner.threads(), 2);
  EXPECT_EQ(tuner.steps_requested() + tuner.steps_fewer(), 180u);
  EXPECT_GE(tuner.steps_fewer(), 20u);
}

TEST(ThreadTuner, ALoneBusyReadingDoesNotDecide) {
  int step = 0;
  ThreadTuner tuner(
      2, 2, [&] { return std::optional<int>(step % 80 == 0 ? 3 : 1); }, 10, 8);
  for (; step < 800; ++step) tuner.record_step();
  EXPECT_EQ(tuner.steps_fewer(), 0u);  // one busy reading in eight averages to 1.25 tasks
}

TEST(ThreadTuner, OneThreadRequestedOrNoCountKeepsTheRequestedThreads) {
  ThreadTuner one(1, 2, [] { return std::optional<int>(5); });
  ThreadTuner blind(2, 2, [] { return std::optional<int>(); });
  for (int s = 0; s < 200; ++s) {
    one.record_step();
    blind.record_step();
  }
  EXPECT_EQ(one.threads(), 1);
  EXPECT_EQ(blind.threads(), 2);
  EXPECT_EQ(blind.steps_requested(), 200u);
}

TEST(ThreadTuner, ReadsTheRunningTasksOfThisMachine) {
  const std::optional<int> running = ThreadTuner::procs_running();
  ASSERT_TRUE(running.has_value());  // Linux's /proc/stat
  EXPECT_GE(*running, 1);            // this test runs
}

}  // namespace
}  // namespace slide::run
