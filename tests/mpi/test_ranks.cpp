// Ranks' collectives on however many ranks mpirun started (common/base/ranks.hpp): each
// result has a closed form in the rank numbers.
#include <cstdint>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "common/base/ranks.hpp"

namespace slide {
namespace {

const Ranks& ranks() {
  return Ranks::world();
}

TEST(Ranks, ThisIsARunOnSeveralRanks) {
  EXPECT_GE(ranks().size(), 2) << "run the MPI tests under mpirun -np 2 or more";
  EXPECT_TRUE(ranks().distributed());
}

TEST(Ranks, ReductionsHaveTheirClosedForms) {
  const int n = ranks().size(), r = ranks().rank();
  EXPECT_EQ(ranks().sum(r + 1.0), n * (n + 1) / 2.0);
  EXPECT_EQ(ranks().min(10.0 - r), 10.0 - (n - 1));
  EXPECT_EQ(ranks().max(10.0 - r), 10.0);
  EXPECT_EQ(ranks().max(std::int64_t{r} * 7), std::int64_t{n - 1} * 7);
  std::vector<double> d{1.0, static_cast<double>(r)};
  ranks().sum(std::span<double>(d));
  EXPECT_EQ(d, (std::vector<double>{1.0 * n, n * (n - 1) / 2.0}));
  std::vector<std::int64_t> i{r, std::int64_t{1} << 40};
  ranks().sum(std::span<std::int64_t>(i));
  EXPECT_EQ(i, (std::vector<std::int64_t>{n * (n - 1) / 2, std::int64_t{n} << 40}));
  EXPECT_EQ(ranks().exclusive_prefix_sum(r + 1), std::int64_t{r} * (r + 1) / 2);
}

TEST(Ranks, ExchangeAroundARing) {
  const int n = ranks().size(), r = ranks().rank();
  // Rank r sends r + 1 copies of its number to the right; the last sends nothing.
  const std::vector<std::int32_t> mine(static_cast<std::size_t>(r) + 1, r);
  const int to = r + 1 < n ? r + 1 : -1, from = r > 0 ? r - 1 : -1;
  const auto got = Ranks::values_of<std::int32_t>(
      ranks().exchange(to, Ranks::bytes_of(std::span<const std::int32_t>(mine)), from));
  if (r == 0) {
    EXPECT_TRUE(got.empty());
  } else {
    EXPECT_EQ(got, std::vector<std::int32_t>(static_cast<std::size_t>(r), r - 1));
  }
}

TEST(Ranks, AllToAllDeliversInRankOrder) {
  const int n = ranks().size(), r = ranks().rank();
  // Rank r sends s + 1 values 100 r + s to rank s (nothing to itself on rank 0).
  std::vector<std::vector<std::byte>> outgoing(static_cast<std::size_t>(n));
  for (int s = 0; s < n; ++s) {
    if (r == 0 && s == 0) continue;
    const std::vector<std::int32_t> v(static_cast<std::size_t>(s) + 1, 100 * r + s);
    const auto b = Ranks::bytes_of(std::span<const std::int32_t>(v));
    outgoing[static_cast<std::size_t>(s)].assign(b.begin(), b.end());
  }
  const auto incoming = ranks().all_to_all(outgoing);
  ASSERT_EQ(incoming.size(), static_cast<std::size_t>(n));
  for (int s = 0; s < n; ++s) {
    const auto got = Ranks::values_of<std::int32_t>(incoming[static_cast<std::size_t>(s)]);
    const std::size_t expected = (s == 0 && r == 0) ? 0 : static_cast<std::size_t>(r) + 1;
    EXPECT_EQ(got, std::vector<std::int32_t>(expected, 100 * s + r)) << "from rank " << s;
  }
}

TEST(Ranks, GatherBroadcastAndFirstProblem) {
  const int n = ranks().size(), r = ranks().rank();
  const std::vector<std::int64_t> mine(2, r);
  const auto all = Ranks::values_of<std::int64_t>(
      ranks().gather_to_root(Ranks::bytes_of(std::span<const std::int64_t>(mine))));
  if (ranks().root()) {
    ASSERT_EQ(all.size(), 2 * static_cast<std::size_t>(n));
    for (int s = 0; s < n; ++s) EXPECT_EQ(all[2 * static_cast<std::size_t>(s) + 1], s);
  } else {
    EXPECT_TRUE(all.empty());
  }
  EXPECT_EQ(ranks().broadcast(r == 0 ? "from the root" : "not this"), "from the root");
  // Every rank above 0 has a problem: all agree on rank 1's.
  const auto problem = ranks().first_problem(
      r > 0 ? std::optional<std::string>("problem of rank " + std::to_string(r)) : std::nullopt);
  ASSERT_TRUE(problem.has_value());
  EXPECT_EQ(*problem, "problem of rank 1");
  EXPECT_FALSE(ranks().first_problem(std::nullopt).has_value());
}

}  // namespace
}  // namespace slide
