// main of the MPI tests (tests/mpi/README.md): every rank runs every test, the root
// prints the usual report, the other ranks only their failures (with their rank), and
// the program fails when a test failed on any rank.
#include <cstdint>
#include <cstdio>

#include <gtest/gtest.h>

#include "common/base/ranks.hpp"

namespace {

class FailuresOfRank : public ::testing::EmptyTestEventListener {
 public:
  explicit FailuresOfRank(int rank) : rank_(rank) {}
  void OnTestPartResult(const ::testing::TestPartResult& result) override {
    if (!result.failed()) return;
    std::fprintf(stderr, "rank %d: %s:%d: failure\n%s\n", rank_,
                 result.file_name() ? result.file_name() : "?", result.line_number(),
                 result.summary());
  }

 private:
  int rank_;
};

}  // namespace

int main(int argc, char** argv) {
  slide::RankSession session(argc, argv);
  ::testing::InitGoogleTest(&argc, argv);
  const slide::Ranks& ranks = slide::Ranks::world();
  if (!ranks.root()) {
    auto& listeners = ::testing::UnitTest::GetInstance()->listeners();
    delete listeners.Release(listeners.default_result_printer());
    listeners.Append(new FailuresOfRank(ranks.rank()));
  }
  const int failed = RUN_ALL_TESTS() != 0 ? 1 : 0;
  return ranks.max(std::int64_t{failed}) == 0 ? 0 : 1;
}
