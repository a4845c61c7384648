// The seeded driver's mutator: deterministic for a seed, different across seeds, the
// corpus first and unchanged, inputs within the size bound, every kind of change made,
// dictionary tokens used, and libFuzzer's dictionary format read as libFuzzer reads it.
#include <algorithm>
#include <fstream>
#include <set>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "tests/fuzz/seeded/mutator.hpp"

namespace slide::fuzz {
namespace {

Bytes bytes(const std::string& text) {
  return Bytes(text.begin(), text.end());
}

Mutator text_mutator(std::vector<Bytes> dictionary = {}, std::size_t max_size = 0) {
  return Mutator({bytes("[mesh]\nelement_size = 1.0\n"), bytes("$Nodes\n1 0 0 0\n$EndNodes\n")},
                 std::move(dictionary), max_size);
}

TEST(FuzzMutator, TheSameSeedAndIterationGiveTheSameInput) {
  const Mutator a = text_mutator(), b = text_mutator();
  for (std::uint64_t i = 0; i < 500; ++i) EXPECT_EQ(a.input(7, i), b.input(7, i)) << i;
}

TEST(FuzzMutator, OtherSeedsGiveOtherInputs) {
  const Mutator m = text_mutator();
  int same = 0;
  for (std::uint64_t i = 2; i < 202; ++i) same += m.input(1, i) == m.input(2, i) ? 1 : 0;
  EXPECT_LT(same, 20);
}

TEST(FuzzMutator, RunsTheCorpusUnchangedFirst) {
  const Mutator m = text_mutator();
  EXPECT_EQ(m.input(3, 0), m.corpus()[0]);
  EXPECT_EQ(m.input(3, 1), m.corpus()[1]);
  EXPECT_NE(m.input(3, 2), m.corpus()[0]);
}

TEST(FuzzMutator, MakesEveryKindOfChangeWithinTheSizeBound) {
  const Mutator m = text_mutator({}, 40);
  int longer = 0, shorter = 0, same_length_changed = 0, at_bound = 0;
  for (std::uint64_t i = 2; i < 2002; ++i) {
    const Bytes input = m.input(11, i);
    ASSERT_LE(input.size(), 40u);
    const bool from_first = std::search(input.begin(), input.end(), m.corpus()[0].begin(),
                                        m.corpus()[0].begin() + 6) != input.end();
    const Bytes& base = m.corpus()[from_first ? 0 : 1];
    longer += input.size() > base.size() ? 1 : 0;
    shorter += input.size() < base.size() ? 1 : 0;
    same_length_changed += input.size() == base.size() && input != base ? 1 : 0;
    at_bound += input.size() == 40u ? 1 : 0;
  }
  EXPECT_GT(longer, 100);
  EXPECT_GT(shorter, 100);
  EXPECT_GT(same_length_changed, 100);
  EXPECT_GT(at_bound, 0);  // long inserts were cut to the bound
}

TEST(FuzzMutator, UsesTheDictionary) {
  const Mutator m = text_mutator({bytes("XYZZY")});
  int with_token = 0;
  for (std::uint64_t i = 2; i < 1002; ++i) {
    const Bytes input = m.input(5, i);
    const Bytes token = bytes("XYZZY");
    with_token +=
        std::search(input.begin(), input.end(), token.begin(), token.end()) != input.end();
  }
  EXPECT_GT(with_token, 50);
}

TEST(FuzzMutator, ReadsLibFuzzerDictionaries) {
  const auto file = std::filesystem::path(::testing::TempDir()) / "fuzz_mutator.dict";
  std::ofstream(file) << "# comment\n\n\"plain\"\nnamed=\"a\\\"b\"\n\"\\x89HDF\\\\\"\n";
  const std::vector<Bytes> tokens = read_dictionary(file);
  ASSERT_EQ(tokens.size(), 3u);
  EXPECT_EQ(tokens[0], bytes("plain"));
  EXPECT_EQ(tokens[1], bytes("a\"b"));
  EXPECT_EQ(tokens[2], (Bytes{0x89, 'H', 'D', 'F', '\\'}));
}

TEST(FuzzMutator, NamesTheLineOfABadDictionaryEntry) {
  const auto file = std::filesystem::path(::testing::TempDir()) / "fuzz_mutator_bad.dict";
  std::ofstream(file) << "\"good\"\nno quotes here\n";
  try {
    read_dictionary(file);
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("fuzz_mutator_bad.dict:2:"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace slide::fuzz
