// The seeded mutation driver's mutator (mutator.hpp).
#include "tests/fuzz/seeded/mutator.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <string_view>

namespace slide::fuzz {

namespace {

// Numbers that sit on a boundary of some check: zero, signs, the limits of the integer
// types, NaN, the infinities, the extremes of double.
constexpr std::array<std::uint64_t, 16> boundary_integers = {
    0,
    1,
    0xffffffffffffffffULL,
    0x7f,
    0x80,
    0xff,
    0x7fff,
    0x8000,
    0xffff,
    0x7fffffff,
    0x80000000,
    0xffffffff,
    0x100000000ULL,
    0x7fffffffffffffffULL,
    0x7ff8000000000000ULL,  // NaN
    0x7ff0000000000000ULL,  // +inf
};

constexpr std::array<std::string_view, 18> boundary_numbers = {
    "0",          "-0",         "1",          "-1",
    "0.5",        "1e308",      "-1e308",     "1e400",
    "1e-320",     "nan",        "inf",        "-inf",
    "2147483647", "2147483648", "4294967296", "9223372036854775808",
    "1e9",        "0x10",
};

std::uint64_t mix(std::uint64_t x) {
  x ^= x >> 30;
  x *= 0xbf58476d1ce4e5b9ULL;
  x ^= x >> 27;
  x *= 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

/// A length of 1 to `limit`, short ones far more often than long ones.
std::size_t chunk_length(Random& random, std::size_t limit) {
  if (limit <= 1) return 1;
  const std::size_t scale = std::size_t{1} << random.below(13);  // 1 to 4096
  return 1 + random.below(std::min(limit, scale));
}

int hex_digit(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

/// The bytes between the quotes of one dictionary line, escapes resolved.
Bytes parse_token(std::string_view quoted, const std::string& where) {
  Bytes token;
  for (std::size_t i = 0; i < quoted.size(); ++i) {
    if (quoted[i] != '\\') {
      token.push_back(static_cast<std::uint8_t>(quoted[i]));
      continue;
    }
    if (i + 1 >= quoted.size()) throw std::runtime_error(where + ": dangling backslash");
    const char escaped = quoted[++i];
    if (escaped == '\\' || escaped == '"') {
      token.push_back(static_cast<std::uint8_t>(escaped));
    } else if (escaped == 'x' && i + 2 < quoted.size() && hex_digit(quoted[i + 1]) >= 0 &&
               hex_digit(quoted[i + 2]) >= 0) {
      token.push_back(
          static_cast<std::uint8_t>(hex_digit(quoted[i + 1]) * 16 + hex_digit(quoted[i + 2])));
      i += 2;
    } else {
      throw std::runtime_error(where + ": unknown escape \\" + std::string(1, escaped));
    }
  }
  return token;
}

}  // namespace

std::uint64_t Random::next() {
  state_ += 0x9e3779b97f4a7c15ULL;
  return mix(state_);
}

std::vector<Bytes> read_dictionary(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) throw std::runtime_error(file.string() + ": cannot read the dictionary");
  std::vector<Bytes> tokens;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    const auto first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    const auto open = line.find('"');
    const auto close = line.find_last_of('"');
    const std::string where = file.string() + ":" + std::to_string(number);
    if (open == std::string::npos || close <= open) {
      throw std::runtime_error(where + ": expected \"token\" or name=\"token\"");
    }
    tokens.push_back(parse_token(std::string_view(line).substr(open + 1, close - open - 1), where));
  }
  return tokens;
}

Mutator::Mutator(std::vector<Bytes> corpus, std::vector<Bytes> dictionary, std::size_t max_size)
    : corpus_(std::move(corpus)), dictionary_(std::move(dictionary)), max_size_(max_size) {
  if (corpus_.empty()) throw std::runtime_error("the corpus is empty");
  for (const Bytes& entry : corpus_) max_size_ = std::max(max_size_, entry.size());
}

Bytes Mutator::input(std::uint64_t seed, std::uint64_t iteration) const {
  if (iteration < corpus_.size()) return corpus_[iteration];
  Random random(mix(seed) ^ mix(iteration + 0x632be59bd9b4e019ULL));
  Bytes data = corpus_[random.below(corpus_.size())];
  // Mostly one or two mutations, now and then a pile of them.
  const std::size_t count = random.one_in(4) ? 1 + random.below(8) : 1 + random.below(2);
  for (std::size_t k = 0; k < count; ++k) mutate_once(data, random);
  if (data.size() > max_size_) data.resize(max_size_);
  return data;
}

void Mutator::mutate_once(Bytes& data, Random& random) const {
  switch (random.below(dictionary_.empty() ? 9 : 11)) {
    case 0:
      flip_bit(data, random);
      break;
    case 1:
      set_byte(data, random);
      break;
    case 2:
      set_boundary_integer(data, random);
      break;
    case 3:
      insert_random(data, random);
      break;
    case 4:
      erase_range(data, random);
      break;
    case 5:
      duplicate_chunk(data, random);
      break;
    case 6:
      splice(data, random);
      break;
    case 7:
      replace_number(data, random);
      break;
    case 8:
      flip_bit(data, random);
      break;  // the cheapest change, twice as often
    default:
      use_token(data, random);
      break;
  }
}

void Mutator::flip_bit(Bytes& data, Random& random) const {
  if (data.empty()) return insert_random(data, random);
  data[random.below(data.size())] ^= static_cast<std::uint8_t>(1u << random.below(8));
}

void Mutator::set_byte(Bytes& data, Random& random) const {
  if (data.empty()) return insert_random(data, random);
  static constexpr std::array<std::uint8_t, 8> boundary = {0, 1, 0x7f, 0x80, 0xfe, 0xff, ' ', '\n'};
  data[random.below(data.size())] = random.one_in(2) ? boundary[random.below(boundary.size())]
                                                     : static_cast<std::uint8_t>(random.next());
}

void Mutator::set_boundary_integer(Bytes& data, Random& random) const {
  static constexpr std::array<std::size_t, 4> widths = {1, 2, 4, 8};
  const std::size_t width = widths[random.below(widths.size())];
  if (data.size() < width) return insert_random(data, random);
  std::uint64_t value = boundary_integers[random.below(boundary_integers.size())];
  if (random.one_in(4)) value += random.below(3) - 1;  // one off the boundary
  const std::size_t at = random.below(data.size() - width + 1);
  for (std::size_t b = 0; b < width; ++b) {  // little-endian, as HDF5 stores our data
    data[at + b] = static_cast<std::uint8_t>(value >> (8 * b));
  }
}

void Mutator::insert_random(Bytes& data, Random& random) const {
  const std::size_t at = random.below(data.size() + 1);
  const std::size_t count = 1 + random.below(16);
  // Made room for, then written in place: GCC 12's vectoriser with AVX-512 (-march=native
  // on some CPUs) warned of a false overflow when the bytes went through a buffer.
  data.insert(data.begin() + static_cast<std::ptrdiff_t>(at), count, std::uint8_t{0});
  for (std::size_t b = 0; b < count; ++b) data[at + b] = static_cast<std::uint8_t>(random.next());
}

void Mutator::erase_range(Bytes& data, Random& random) const {
  if (data.empty()) return;
  const std::size_t at = random.below(data.size());
  const std::size_t length = chunk_length(random, data.size() - at);
  data.erase(data.begin() + static_cast<std::ptrdiff_t>(at),
             data.begin() + static_cast<std::ptrdiff_t>(at + length));
}

void Mutator::duplicate_chunk(Bytes& data, Random& random) const {
  if (data.empty()) return insert_random(data, random);
  const std::size_t from = random.below(data.size());
  const std::size_t length = chunk_length(random, data.size() - from);
  const Bytes chunk(data.begin() + static_cast<std::ptrdiff_t>(from),
                    data.begin() + static_cast<std::ptrdiff_t>(from + length));
  const std::size_t to = random.below(data.size() + 1);
  data.insert(data.begin() + static_cast<std::ptrdiff_t>(to), chunk.begin(), chunk.end());
}

void Mutator::splice(Bytes& data, Random& random) const {
  const Bytes& other = corpus_[random.below(corpus_.size())];
  if (other.empty()) return erase_range(data, random);
  const std::size_t from = random.below(other.size());
  const std::size_t length = chunk_length(random, other.size() - from);
  const auto begin = other.begin() + static_cast<std::ptrdiff_t>(from);
  const auto end = begin + static_cast<std::ptrdiff_t>(length);
  if (random.one_in(2) && from + length <= data.size()) {
    // Same place in the other file: files of one writer share their layout.
    std::copy(begin, end, data.begin() + static_cast<std::ptrdiff_t>(from));
  } else {
    const std::size_t to = random.below(data.size() + 1);
    data.insert(data.begin() + static_cast<std::ptrdiff_t>(to), begin, end);
  }
}

void Mutator::use_token(Bytes& data, Random& random) const {
  const Bytes& token = dictionary_[random.below(dictionary_.size())];
  if (random.one_in(2) && data.size() >= token.size()) {
    const std::size_t at = random.below(data.size() - token.size() + 1);
    std::copy(token.begin(), token.end(), data.begin() + static_cast<std::ptrdiff_t>(at));
  } else {
    const std::size_t at = random.below(data.size() + 1);
    data.insert(data.begin() + static_cast<std::ptrdiff_t>(at), token.begin(), token.end());
  }
}

void Mutator::replace_number(Bytes& data, Random& random) const {
  const auto is_number_byte = [](std::uint8_t b) {
    return std::isdigit(b) != 0 || b == '.' || b == '-' || b == '+' || b == 'e' || b == 'E';
  };
  // The first digit at or after a random place, and the whole number around it.
  const std::size_t start = data.empty() ? 0 : random.below(data.size());
  const auto digit = std::find_if(data.begin() + static_cast<std::ptrdiff_t>(start), data.end(),
                                  [](std::uint8_t b) { return std::isdigit(b) != 0; });
  if (digit == data.end()) return set_boundary_integer(data, random);
  auto begin = digit, end = digit;
  while (begin != data.begin() && is_number_byte(*(begin - 1))) --begin;
  while (end != data.end() && is_number_byte(*end)) ++end;
  const std::string_view number = boundary_numbers[random.below(boundary_numbers.size())];
  const auto at = data.erase(begin, end);
  data.insert(at, number.begin(), number.end());
}

}  // namespace slide::fuzz
