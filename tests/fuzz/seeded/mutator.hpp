// The seeded mutation driver's mutator: deterministic inputs for the fuzz drivers
// without libFuzzer (any compiler, the default test suite). Input number i of a run with
// seed s is a function of (s, i) and the corpus alone: no coverage feedback, no state
// carried from one input to the next, so `--seed s --only i` rebuilds any input exactly.
//
// An input is a corpus entry with 1 to 8 stacked mutations, each one of: flip a bit,
// set a byte to a random or a boundary value, overwrite 2, 4 or 8 bytes with a boundary
// integer, insert random bytes, delete a range, duplicate a chunk elsewhere, splice in a
// chunk of another entry, insert or overwrite with a dictionary token, and for text
// replace a number with another one.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace slide::fuzz {

using Bytes = std::vector<std::uint8_t>;

/// SplitMix64 (Steele, Lea, Flood 2014): small, fast, and the same numbers on every
/// platform (unlike the standard distributions).
class Random {
 public:
  explicit Random(std::uint64_t seed) : state_(seed) {}
  std::uint64_t next();
  /// Uniform in [0, n) for n ≥ 1 (the modulo bias is irrelevant here).
  std::size_t below(std::size_t n) { return static_cast<std::size_t>(next() % n); }
  bool one_in(std::size_t n) { return below(n) == 0; }

 private:
  std::uint64_t state_;
};

/// The tokens of a libFuzzer dictionary file: one `"token"` or `name="token"` per line,
/// `#` comments, escapes \\, \" and \xNN. Throws std::runtime_error naming the line of a
/// malformed entry.
std::vector<Bytes> read_dictionary(const std::filesystem::path& file);

class Mutator {
 public:
  /// `corpus` must not be empty; `max_size` bounds the inputs (at least the largest entry).
  Mutator(std::vector<Bytes> corpus, std::vector<Bytes> dictionary, std::size_t max_size);

  /// Input `iteration` of the run with `seed`: the corpus entries as they are for the
  /// first corpus().size() iterations, mutated entries after them.
  Bytes input(std::uint64_t seed, std::uint64_t iteration) const;

  const std::vector<Bytes>& corpus() const { return corpus_; }

 private:
  void mutate_once(Bytes& data, Random& random) const;
  void flip_bit(Bytes& data, Random& random) const;
  void set_byte(Bytes& data, Random& random) const;
  void set_boundary_integer(Bytes& data, Random& random) const;
  void insert_random(Bytes& data, Random& random) const;
  void erase_range(Bytes& data, Random& random) const;
  void duplicate_chunk(Bytes& data, Random& random) const;
  void splice(Bytes& data, Random& random) const;
  void use_token(Bytes& data, Random& random) const;
  void replace_number(Bytes& data, Random& random) const;

  std::vector<Bytes> corpus_;
  std::vector<Bytes> dictionary_;
  std::size_t max_size_;
};

}  // namespace slide::fuzz
