// The seeded mutation driver: runs one fuzz driver (LLVMFuzzerTestOneInput, linked in)
// on deterministic mutations of a corpus, without libFuzzer, so that the default test
// suite fuzzes every reader with the default compiler (tests/fuzz/README.md).
//
//   fuzz_seeded_gmsh --seed 1 --runs 4000 --dict gmsh.dict --valid GOOD.msh CORPUS_DIR...
//   fuzz_seeded_gmsh --seed 1 --only 1234 --write-input crash.msh CORPUS_DIR...
//   fuzz_seeded_gmsh crash.msh                 (run files once, as libFuzzer would)
//
// Inputs run in batches, each in a forked child with an alarm per input, so a crash, a
// hang or an exception other than slide::Error ends one batch only: the driver names
// the input (seed and number, and how to rebuild it), saves it with --crash-dir, and
// goes on with the next input. The exit status is 1 when there was any finding or a
// --valid entry was rejected, 2 on a bad command line.
#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <typeinfo>
#include <vector>

#include <cxxabi.h>
#include <fcntl.h>
#include <fmt/format.h>
#include <sys/mman.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include "tests/fuzz/fuzz_support.hpp"
#include "tests/fuzz/seeded/mutator.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

namespace {

// Under AddressSanitizer (tools/sanitize.sh) the children get no address-space limit:
// ASan reserves terabytes of shadow memory at start, so under RLIMIT_AS every later
// mapping fails ("Failed to mmap") and every input would be a finding. The --memory-mb
// bound is then kept by the default build's run of the same test.
#if defined(__SANITIZE_ADDRESS__)
constexpr bool address_sanitizer = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
constexpr bool address_sanitizer = true;
#else
constexpr bool address_sanitizer = false;
#endif
#else
constexpr bool address_sanitizer = false;
#endif

namespace fs = std::filesystem;
using slide::fuzz::Bytes;
using slide::fuzz::Mutator;
using slide::fuzz::report;

struct Options {
  std::vector<fs::path> entries;  ///< corpus files and folders
  std::vector<fs::path> valid;    ///< corpus entries that must be accepted whole
  std::optional<fs::path> dictionary;
  std::uint64_t seed = 1;
  std::optional<std::uint64_t> runs;  ///< unset: each corpus entry once
  std::uint64_t first = 0;            ///< number of the first input
  std::optional<std::uint64_t> only;
  std::optional<fs::path> write_input;
  std::optional<fs::path> crash_dir;
  unsigned timeout = 10;  ///< s per input
  std::uint64_t batch = 100;
  std::size_t max_len = 0;  ///< 0: the largest entry plus 4 kB
  std::uint64_t memory_mb = 4096;
  int max_findings = 0;  ///< stop after this many (0: never)
  bool verbose = false;
};

/// What a child tells its parent, in memory they share.
struct Shared {
  std::uint64_t current = 0;  ///< the input running now
  std::uint64_t done = 0;     ///< inputs finished
  std::uint64_t mutants_accepted = 0;
  char message[1024] = {};  ///< an escaped exception
  // Followed by one flag per corpus entry: accepted as it is.
};

struct Corpus {
  std::vector<Bytes> entries;
  std::vector<std::string> names;
  std::vector<bool> must_accept;
};

const char* program = "fuzz_seeded";

[[noreturn]] void usage(const std::string& problem) {
  report(fmt::format("{}: {}", program, problem));
  report(fmt::format(
      "usage: {} [--seed N] [[--first I] --runs N | --only I [--write-input FILE]] [--dict FILE] "
      "[--valid ENTRY]... [--crash-dir DIR] [--timeout S] [--batch N] [--max-len N] "
      "[--memory-mb N] [--max-findings N] [--verbose] ENTRY...",
      program));
  std::exit(2);
}

std::uint64_t number(const char* text, const char* option) {
  char* end = nullptr;
  const unsigned long long value = std::strtoull(text, &end, 10);
  if (end == text || *end != '\0')
    usage(fmt::format("{} {}: expected a whole number", option, text));
  return value;
}

Options parse_options(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const auto value = [&]() -> const char* {
      if (i + 1 >= argc) usage(arg + " needs a value");
      return argv[++i];
    };
    if (arg == "--seed")
      o.seed = number(value(), "--seed");
    else if (arg == "--runs")
      o.runs = number(value(), "--runs");
    else if (arg == "--first")
      o.first = number(value(), "--first");
    else if (arg == "--only")
      o.only = number(value(), "--only");
    else if (arg == "--write-input")
      o.write_input = value();
    else if (arg == "--dict")
      o.dictionary = value();
    else if (arg == "--valid")
      o.valid.emplace_back(value());
    else if (arg == "--crash-dir")
      o.crash_dir = value();
    else if (arg == "--timeout")
      o.timeout = static_cast<unsigned>(number(value(), "--timeout"));
    else if (arg == "--batch")
      o.batch = std::max<std::uint64_t>(1, number(value(), "--batch"));
    else if (arg == "--max-len")
      o.max_len = number(value(), "--max-len");
    else if (arg == "--memory-mb")
      o.memory_mb = number(value(), "--memory-mb");
    else if (arg == "--max-findings")
      o.max_findings = static_cast<int>(number(value(), "--max-findings"));
    else if (arg == "--verbose")
      o.verbose = true;
    else if (arg.starts_with("--"))
      usage("unknown option " + arg);
    else
      o.entries.emplace_back(arg);
  }
  if (o.entries.empty() && o.valid.empty()) usage("no corpus");
  if (o.runs && o.only) usage("--runs and --only exclude each other");
  if (o.first > 0 && !o.runs) usage("--first needs --runs");
  if (o.write_input && !o.only) usage("--write-input needs --only");
  return o;
}

Bytes read_file(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw std::runtime_error(file.string() + ": cannot read");
  return Bytes(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

/// The files of an entry: the file itself, or a folder's regular files sorted by name.
std::vector<fs::path> files_of(const fs::path& entry) {
  if (!fs::is_directory(entry)) return {entry};
  std::vector<fs::path> files;
  for (const auto& item : fs::directory_iterator(entry))
    if (item.is_regular_file()) files.push_back(item.path());
  std::sort(files.begin(), files.end());
  if (files.empty()) throw std::runtime_error(entry.string() + ": no files in the corpus folder");
  return files;
}

Corpus load_corpus(const Options& o) {
  Corpus corpus;
  const auto add = [&](const fs::path& entry, bool must_accept) {
    for (const fs::path& file : files_of(entry)) {
      corpus.entries.push_back(read_file(file));
      corpus.names.push_back(file.string());
      corpus.must_accept.push_back(must_accept);
    }
  };
  for (const auto& entry : o.valid) add(entry, true);
  for (const auto& entry : o.entries) add(entry, false);
  return corpus;
}

std::string type_name(const std::type_info& type) {
  int status = 0;
  std::unique_ptr<char, decltype(&std::free)> name(
      abi::__cxa_demangle(type.name(), nullptr, nullptr, &status), &std::free);
  return status == 0 && name ? std::string(name.get()) : std::string(type.name());
}

/// One input in the child; an exception other than slide::Error ends the child.
bool run_input(const Bytes& data, Shared& shared) {
  const std::uint64_t before = slide::fuzz::accepted_count();
  try {
    LLVMFuzzerTestOneInput(data.data(), data.size());
  } catch (const std::exception& e) {
    std::snprintf(shared.message, sizeof shared.message, "uncaught %s: %s",
                  type_name(typeid(e)).c_str(), e.what());
    std::exit(70);
  } catch (...) {
    std::snprintf(shared.message, sizeof shared.message, "uncaught exception of unknown type");
    std::exit(70);
  }
  return slide::fuzz::accepted_count() > before;
}

/// The child: inputs [begin, end) with an alarm each, then a normal exit (which runs the
/// scratch folder's clean-up).
[[noreturn]] void run_batch(const Mutator& mutator, const Options& o, std::uint64_t begin,
                            std::uint64_t end, Shared& shared, bool* seed_accepted) {
  if (!o.verbose) {  // the programs' warnings would drown the report
    const int null = ::open("/dev/null", O_WRONLY);
    ::dup2(null, 1);
    ::dup2(null, 2);
  }
  if (!address_sanitizer) {
    const rlim_t bytes = static_cast<rlim_t>(o.memory_mb) << 20;
    const rlimit limit{bytes, bytes};
    ::setrlimit(RLIMIT_AS, &limit);
  }
  for (std::uint64_t i = begin; i < end; ++i) {
    shared.current = i;
    const Bytes data = mutator.input(o.seed, i);
    ::alarm(o.timeout);
    const bool accepted = run_input(data, shared);
    ::alarm(0);
    if (i < mutator.corpus().size()) {
      seed_accepted[i] = accepted;
    } else if (accepted) {
      ++shared.mutants_accepted;
    }
    shared.done = i + 1;
  }
  std::exit(0);
}

std::string describe_status(int status, const Shared& shared, unsigned timeout) {
  if (WIFSIGNALED(status)) {
    const int signal = WTERMSIG(status);
    if (signal == SIGALRM) return fmt::format("hang: no answer within {} s", timeout);
    return fmt::format("killed by signal {} ({})", signal, ::strsignal(signal));
  }
  if (WEXITSTATUS(status) == 70) return shared.message;
  return fmt::format("exited with status {}", WEXITSTATUS(status));
}

class Run {
 public:
  Run(const Options& o, Corpus corpus)
      : o_(o),
        names_(std::move(corpus.names)),
        must_accept_(std::move(corpus.must_accept)),
        mutator_(make_mutator(o, std::move(corpus.entries))) {
    const std::size_t bytes = sizeof(Shared) + names_.size();
    void* memory =
        ::mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_SHARED | MAP_ANONYMOUS, -1, 0);
    if (memory == MAP_FAILED) throw std::runtime_error("cannot map the shared memory");
    shared_ = new (memory) Shared();
    seed_accepted_ = reinterpret_cast<bool*>(static_cast<char*>(memory) + sizeof(Shared));
    std::fill(seed_accepted_, seed_accepted_ + names_.size(), false);
  }

  /// Inputs [begin, end), batch by batch; returns the number of findings.
  int execute(std::uint64_t begin, std::uint64_t end) {
    const auto started = std::chrono::steady_clock::now();
    int findings = 0;
    for (std::uint64_t next = begin; next < end;) {
      const std::uint64_t stop = std::min(end, next + o_.batch);
      shared_->done = next;
      shared_->current = next;
      std::fflush(nullptr);
      const pid_t child = ::fork();
      if (child < 0) throw std::runtime_error("cannot fork");
      if (child == 0) run_batch(mutator_, o_, next, stop, *shared_, seed_accepted_);
      int status = 0;
      ::waitpid(child, &status, 0);
      if (WIFEXITED(status) && WEXITSTATUS(status) == 0 && shared_->done == stop) {
        next = stop;
        continue;
      }
      std::error_code ignored;
      fs::remove_all(slide::fuzz::scratch_folder_of(child), ignored);
      record_finding(shared_->current, next, describe_status(status, *shared_, o_.timeout));
      ++findings;
      next = shared_->current + 1;
      if (o_.max_findings > 0 && findings >= o_.max_findings) {
        report(fmt::format("{}: stopped after {} finding(s) (--max-findings)", program, findings));
        end = next;
        break;
      }
    }
    last_ = end;
    seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    return findings;
  }

  /// The --valid entries that were rejected, each reported.
  int rejected_valid_entries(std::uint64_t begin, std::uint64_t end) const {
    int rejected = 0;
    for (std::size_t k = begin; k < names_.size() && k < end; ++k) {
      if (must_accept_[k] && !seed_accepted_[k]) {
        report(
            fmt::format("{}: FAILED: the valid corpus entry {} was rejected", program, names_[k]));
        ++rejected;
      }
    }
    return rejected;
  }

  void summarise(std::uint64_t begin, std::uint64_t end, int findings) const {
    // Inputs below corpus_size() are the corpus entries, the others mutants.
    const std::uint64_t seeds_end = std::min<std::uint64_t>(end, names_.size());
    const std::uint64_t seeds_begin = std::min(begin, seeds_end);
    const std::uint64_t seeds_run = seeds_end - seeds_begin;
    const auto seeds_accepted =
        std::count(seed_accepted_ + seeds_begin, seed_accepted_ + seeds_end, true);
    const std::uint64_t inputs = end - begin;
    report(fmt::format(
        "{}: seed {}, {} inputs in {:.1f} s ({:.0f}/s): corpus entries accepted {} of {}, "
        "mutants accepted {} of {}, findings {}",
        program, o_.seed, inputs, seconds_,
        seconds_ > 0 ? static_cast<double>(inputs) / seconds_ : 0.0, seeds_accepted, seeds_run,
        shared_->mutants_accepted, inputs - seeds_run, findings));
  }

  std::uint64_t corpus_size() const { return names_.size(); }
  /// One past the last input run (less than asked for after --max-findings).
  std::uint64_t last() const { return last_; }

  void write_input(std::uint64_t iteration, const fs::path& file) const {
    const Bytes data = mutator_.input(o_.seed, iteration);
    if (!file.parent_path().empty()) fs::create_directories(file.parent_path());
    std::ofstream(file, std::ios::binary)
        .write(reinterpret_cast<const char*>(data.data()),
               static_cast<std::streamsize>(data.size()));
  }

 private:
  static Mutator make_mutator(const Options& o, std::vector<Bytes> entries) {
    std::size_t largest = 0;
    for (const Bytes& entry : entries) largest = std::max(largest, entry.size());
    auto dictionary =
        o.dictionary ? slide::fuzz::read_dictionary(*o.dictionary) : std::vector<Bytes>{};
    return Mutator(std::move(entries), std::move(dictionary),
                   o.max_len > 0 ? o.max_len : largest + 4096);
  }

  /// A finding at input `iteration` of the batch that began at input `batch_begin`.
  void record_finding(std::uint64_t iteration, std::uint64_t batch_begin,
                      const std::string& what) const {
    const std::string origin = iteration < names_.size()
                                   ? fmt::format("corpus entry {}", names_[iteration])
                                   : fmt::format("mutant {} of seed {}", iteration, o_.seed);
    report(fmt::format("{}: FINDING: input {} ({}): {}", program, iteration, origin, what));
    report(fmt::format("{}:   rebuild it: {} --seed {} --only {} --write-input FILE <same corpus>",
                       program, program, o_.seed, iteration));
    if (iteration > batch_begin) {
      report(
          fmt::format("{}:   if it passes alone, rerun its batch (state carried from input to "
                      "input): {} --seed "
                      "{} --first {} --runs {} <same corpus>",
                      program, program, o_.seed, batch_begin, iteration - batch_begin + 1));
    }
    if (o_.crash_dir) {
      const fs::path file = *o_.crash_dir / fmt::format("seed{}-input{}", o_.seed, iteration);
      write_input(iteration, file);
      report(fmt::format("{}:   saved as {}", program, file.string()));
    }
  }

  const Options& o_;
  std::vector<std::string> names_;
  std::vector<bool> must_accept_;
  Mutator mutator_;
  Shared* shared_ = nullptr;
  bool* seed_accepted_ = nullptr;
  double seconds_ = 0.0;
  std::uint64_t last_ = 0;  ///< one past the last input run
};

}  // namespace

int main(int argc, char** argv) {
  program = argc > 0 ? argv[0] : program;
  if (const char* slash = std::strrchr(program, '/')) program = slash + 1;
  const Options o = parse_options(argc, argv);
  try {
    Run run(o, load_corpus(o));
    std::uint64_t begin = o.first, end = o.first + o.runs.value_or(run.corpus_size());
    if (o.only) {
      begin = *o.only;
      end = begin + 1;
      if (o.write_input) run.write_input(begin, *o.write_input);
    }
    const int findings = run.execute(begin, end);
    end = run.last();
    const int rejected = o.only ? 0 : run.rejected_valid_entries(begin, end);
    run.summarise(begin, end, findings);
    return findings == 0 && rejected == 0 ? 0 : 1;
  } catch (const std::exception& e) {
    report(fmt::format("{}: {}", program, e.what()));
    return 2;
  }
}
