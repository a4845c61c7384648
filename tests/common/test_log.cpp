// Logger and Progress as logs, CI and Make see them (stdout is not a terminal here):
// plain progress lines every 10 % of the simulated span with an ETA, nothing but the
// summary with --quiet, warnings never silenced.
#include <string>

#include <gtest/gtest.h>

#include "common/base/log.hpp"

namespace slide {
namespace {

std::size_t count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

TEST(Progress, PlainLinesEveryTenthOfTheSpanWithAnEta) {
  const Logger log("prog");
  testing::internal::CaptureStdout();
  {
    Progress progress(log, "stage", 2.0, 4.0);
    for (int step = 1; step <= 200; ++step) progress.update(2.0 + 0.01 * step, step, "KE 1");
    progress.finish();
  }
  const std::string out = testing::internal::GetCapturedStdout();
  // Ten lines (10 %, 20 %, ..., 100 %) and the final "done" line.
  EXPECT_EQ(count(out, "prog: stage t="), 10u) << out;
  EXPECT_EQ(count(out, " eta "), 10u) << out;
  EXPECT_NE(out.find("t=2.200/4.000 s (10%) step 20"), std::string::npos) << out;
  EXPECT_NE(out.find("t=4.000/4.000 s (100%) step 200"), std::string::npos) << out;
  EXPECT_NE(out.find("prog: stage done in "), std::string::npos) << out;
  EXPECT_EQ(out.find('\r'), std::string::npos) << "no in-place redraw off a terminal";
}

TEST(Progress, QuietPrintsOnlyResultsAndWarnings) {
  const Logger log("prog", /*quiet=*/true);
  testing::internal::CaptureStdout();
  testing::internal::CaptureStderr();
  {
    Progress progress(log, "stage", 0.0, 1.0);
    for (int step = 1; step <= 10; ++step) progress.update(0.1 * step, step);
    log.info("hidden {}", 1);
    log.warning("shown {}", 2);
    progress.finish();
    log.result("summary: steps={}", 10);
  }
  const std::string out = testing::internal::GetCapturedStdout();
  const std::string err = testing::internal::GetCapturedStderr();
  EXPECT_EQ(out, "summary: steps=10\n");
  EXPECT_EQ(err, "prog: warning: shown 2\n");
}

}  // namespace
}  // namespace slide
