// prefer_yielding_threads (common/base/program.hpp) as a program sees it: prints the
// GOMP_SPINCOUNT and OMP_WAIT_POLICY it runs with after the call, and how many times it
// started (the environment counts the starts in SLIDE_TEST_STARTS).
#include <cstdio>
#include <cstdlib>
#include <string>

#include "common/base/program.hpp"

int main(int, char** argv) {
  const char* before = std::getenv("SLIDE_TEST_STARTS");
  const std::string starts = std::to_string((before != nullptr ? std::atoi(before) : 0) + 1);
  setenv("SLIDE_TEST_STARTS", starts.c_str(), 1);
  slide::prefer_yielding_threads(argv);
  const char* spin = std::getenv("GOMP_SPINCOUNT");
  const char* policy = std::getenv("OMP_WAIT_POLICY");
  std::printf("GOMP_SPINCOUNT=%s OMP_WAIT_POLICY=%s starts=%s\n", spin ? spin : "unset",
              policy ? policy : "unset", std::getenv("SLIDE_TEST_STARTS"));
}
