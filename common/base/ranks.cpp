#include "common/base/ranks.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <mutex>
#include <new>
#include <thread>

#include <fmt/format.h>

#include "common/base/error.hpp"
#include "common/base/program.hpp"

namespace slide {

std::size_t RowSpan::last_rows_within(std::size_t n, std::size_t tail) const {
  const std::size_t tail_begin = n - std::min(tail, n);
  return end > tail_begin ? end - std::max(first, tail_begin) : 0;
}

RowSpan Part::rows(std::size_t n) const {
  if (parts < 1 || index < 0 || index >= parts)
    throw Error("part {} of {} of a set of rows", index, parts);
  const auto k = static_cast<std::size_t>(index), m = static_cast<std::size_t>(parts);
  return {k * n / m, (k + 1) * n / m};
}

namespace {

Ranks* world_ranks = nullptr;

}  // namespace

Ranks& Ranks::single() {
  static Ranks alone;  // rank 0 of 1; in the MPI build its operations never call MPI
  return alone;
}

Ranks& Ranks::world() {
  // A program (or a test) that opened no session is one process.
  return world_ranks != nullptr ? *world_ranks : single();
}

#if SLIDE_MPI

namespace {

int mpi_count(std::size_t n) {
  if (n > static_cast<std::size_t>(std::numeric_limits<int>::max()))
    throw Error("MPI: a message of {} bytes is beyond MPI's int counts", n);
  return static_cast<int>(n);
}

}  // namespace

double Ranks::sum(double value) const {
  if (size_ == 1) return value;
  double total = 0.0;
  MPI_Allreduce(&value, &total, 1, MPI_DOUBLE, MPI_SUM, communicator_);
  return total;
}

void Ranks::sum(std::span<double> values) const {
  if (size_ == 1 || values.empty()) return;
  MPI_Allreduce(MPI_IN_PLACE, values.data(), mpi_count(values.size()), MPI_DOUBLE, MPI_SUM,
                communicator_);
}

void Ranks::sum(std::span<std::int64_t> values) const {
  if (size_ == 1 || values.empty()) return;
  MPI_Allreduce(MPI_IN_PLACE, values.data(), mpi_count(values.size()), MPI_INT64_T, MPI_SUM,
                communicator_);
}

double Ranks::min(double value) const {
  if (size_ == 1) return value;
  double result = value;
  MPI_Allreduce(&value, &result, 1, MPI_DOUBLE, MPI_MIN, communicator_);
  return result;
}

double Ranks::max(double value) const {
  if (size_ == 1) return value;
  double result = value;
  MPI_Allreduce(&value, &result, 1, MPI_DOUBLE, MPI_MAX, communicator_);
  return result;
}

std::int64_t Ranks::max(std::int64_t value) const {
  if (size_ == 1) return value;
  std::int64_t result = value;
  MPI_Allreduce(&value, &result, 1, MPI_INT64_T, MPI_MAX, communicator_);
  return result;
}

std::int64_t Ranks::exclusive_prefix_sum(std::int64_t value) const {
  if (size_ == 1) return 0;
  std::int64_t below = 0;
  MPI_Exscan(&value, &below, 1, MPI_INT64_T, MPI_SUM, communicator_);
  return rank_ == 0 ? 0 : below;  // MPI leaves rank 0's result undefined
}

std::vector<std::byte> Ranks::exchange(int to, std::span<const std::byte> bytes, int from) const {
  if (size_ == 1)
    return to == 0 && from == 0 ? std::vector<std::byte>(bytes.begin(), bytes.end())
                                : std::vector<std::byte>{};
  const int destination = to < 0 ? MPI_PROC_NULL : to;
  const int source = from < 0 ? MPI_PROC_NULL : from;
  // Sizes first, then the data: the receiver sizes its buffer exactly.
  std::uint64_t outgoing = bytes.size(), incoming = 0;
  MPI_Sendrecv(&outgoing, 1, MPI_UINT64_T, destination, 1, &incoming, 1, MPI_UINT64_T, source, 1,
               communicator_, MPI_STATUS_IGNORE);
  std::vector<std::byte> received(source == MPI_PROC_NULL ? 0 : incoming);
  MPI_Sendrecv(bytes.data(), mpi_count(bytes.size()), MPI_BYTE, destination, 2, received.data(),
               mpi_count(received.size()), MPI_BYTE, source, 2, communicator_, MPI_STATUS_IGNORE);
  return received;
}

std::vector<std::vector<std::byte>> Ranks::all_to_all(
    const std::vector<std::vector<std::byte>>& outgoing) const {
  const auto n = static_cast<std::size_t>(size_);
  if (outgoing.size() != n)
    throw Error("Ranks::all_to_all: {} buffers for {} ranks", outgoing.size(), n);
  if (size_ == 1) return outgoing;
  std::vector<int> send_counts(n), receive_counts(n), send_offsets(n), receive_offsets(n);
  std::vector<std::byte> send;
  for (std::size_t r = 0; r < n; ++r) {
    send_offsets[r] = mpi_count(send.size());
    send_counts[r] = mpi_count(outgoing[r].size());
    send.insert(send.end(), outgoing[r].begin(), outgoing[r].end());
  }
  MPI_Alltoall(send_counts.data(), 1, MPI_INT, receive_counts.data(), 1, MPI_INT, communicator_);
  std::size_t total = 0;
  for (std::size_t r = 0; r < n; ++r) {
    receive_offsets[r] = mpi_count(total);
    total += static_cast<std::size_t>(receive_counts[r]);
  }
  std::vector<std::byte> received(total);
  MPI_Alltoallv(send.data(), send_counts.data(), send_offsets.data(), MPI_BYTE, received.data(),
                receive_counts.data(), receive_offsets.data(), MPI_BYTE, communicator_);
  std::vector<std::vector<std::byte>> incoming(n);
  for (std::size_t r = 0; r < n; ++r) {
    const auto begin = received.begin() + receive_offsets[r];
    incoming[r].assign(begin, begin + receive_counts[r]);
  }
  return incoming;
}

std::vector<std::byte> Ranks::gather_to_root(std::span<const std::byte> bytes) const {
  if (size_ == 1) return {bytes.begin(), bytes.end()};
  const int count = mpi_count(bytes.size());
  std::vector<int> counts(root() ? static_cast<std::size_t>(size_) : 0);
  MPI_Gather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, communicator_);
  std::vector<int> offsets(counts.size());
  std::size_t total = 0;
  for (std::size_t r = 0; r < counts.size(); ++r) {
    offsets[r] = mpi_count(total);
    total += static_cast<std::size_t>(counts[r]);
  }
  std::vector<std::byte> gathered(total);
  MPI_Gatherv(bytes.data(), count, MPI_BYTE, gathered.data(), counts.data(), offsets.data(),
              MPI_BYTE, 0, communicator_);
  return gathered;
}

std::string Ranks::broadcast(std::string text) const {
  if (size_ == 1) return text;
  std::uint64_t length = text.size();
  MPI_Bcast(&length, 1, MPI_UINT64_T, 0, communicator_);
  text.resize(length);
  MPI_Bcast(text.data(), mpi_count(length), MPI_CHAR, 0, communicator_);
  return text;
}

void Ranks::barrier() const {
  if (size_ > 1) MPI_Barrier(communicator_);
}

std::optional<std::string> Ranks::first_problem(const std::optional<std::string>& local) const {
  return first_problem_within(local, std::numeric_limits<double>::infinity());
}

namespace {

std::mutex abort_files_mutex;
std::vector<std::string> abort_files;  ///< Ranks::remove_on_abort's list
std::string program_name = "slide";    ///< for the line before an abort

/// The one line, the files of remove_on_abort removed, every rank ended.
[[noreturn]] void end_all(MPI_Comm communicator, int rank, const std::string& message) {
  fmt::print(stderr, "{}: error: rank {}: {}\n", program_name, rank, message);
  std::fflush(stderr);
  {
    const std::lock_guard lock(abort_files_mutex);
    for (const std::string& file : abort_files) std::remove(file.c_str());
  }
  MPI_Abort(communicator, 1);
  std::abort();  // not reached: MPI_Abort ends this process too
}

}  // namespace

void Ranks::remove_on_abort(const std::string& path) {
  const std::lock_guard lock(abort_files_mutex);
  abort_files.push_back(path);
}

void Ranks::keep_on_abort(const std::string& path) {
  const std::lock_guard lock(abort_files_mutex);
  std::erase(abort_files, path);
}

std::optional<std::string> Ranks::first_problem_within(const std::optional<std::string>& local,
                                                       double grace_seconds) const {
  if (size_ == 1) return local;
  int mine = local ? rank_ : size_, first = size_;
  MPI_Request request = MPI_REQUEST_NULL;
  MPI_Iallreduce(&mine, &first, 1, MPI_INT, MPI_MIN, communicator_, &request);
  if (!local || !std::isfinite(grace_seconds)) {
    MPI_Wait(&request, MPI_STATUS_IGNORE);
  } else {
    const auto deadline = std::chrono::steady_clock::now() +
                          std::chrono::duration<double>(std::max(0.0, grace_seconds));
    int done = 0;
    while (!done) {
      MPI_Test(&request, &done, MPI_STATUS_IGNORE);
      if (done) break;
      if (std::chrono::steady_clock::now() > deadline) end_all(communicator_, rank_, *local);
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
  }
  if (first == size_) return std::nullopt;
  std::string text = rank_ == first ? *local : std::string();
  std::uint64_t length = text.size();
  MPI_Bcast(&length, 1, MPI_UINT64_T, first, communicator_);
  text.resize(length);
  MPI_Bcast(text.data(), mpi_count(length), MPI_CHAR, first, communicator_);
  return text;
}

int Ranks::fail(const std::string& program, const std::string& message) const {
  if (size_ == 1) {
    fmt::print(stderr, "{}: error: {}\n", program, message);
    return 1;
  }
  // Did every rank fail here? A non-blocking barrier on a communicator of its own
  // completes only if all ranks enter it: they all threw (a bad case file, an agreed
  // instability). A rank that failed alone finds its peers blocked in a step's
  // exchange; after the grace period it reports and ends them all.
  MPI_Request request = MPI_REQUEST_NULL;
  MPI_Ibarrier(failure_communicator_, &request);
  int done = 0;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(3);
  while (!done && std::chrono::steady_clock::now() < deadline) {
    MPI_Test(&request, &done, MPI_STATUS_IGNORE);
    if (!done) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  if (done) {
    if (root()) fmt::print(stderr, "{}: error: {}\n", program, message);
    return 1;
  }
  program_name = program;
  end_all(communicator_, rank_, message);
}

RankSession::RankSession(int& argc, char**& argv) {
  int provided = 0;
  // OpenMP threads inside a rank, MPI calls from the main thread only.
  MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
  static Ranks ranks;
  MPI_Comm_dup(MPI_COMM_WORLD, &ranks.communicator_);
  MPI_Comm_dup(MPI_COMM_WORLD, &ranks.failure_communicator_);
  MPI_Comm_rank(ranks.communicator_, &ranks.rank_);
  MPI_Comm_size(ranks.communicator_, &ranks.size_);
  MPI_Comm machine = MPI_COMM_NULL;
  MPI_Comm_split_type(ranks.communicator_, MPI_COMM_TYPE_SHARED, ranks.rank_, MPI_INFO_NULL,
                      &machine);
  MPI_Comm_size(machine, &ranks.machine_size_);
  MPI_Comm_free(&machine);
  world_ranks = &ranks;
}

RankSession::~RankSession() {
  if (world_ranks != nullptr) {
    MPI_Comm_free(&world_ranks->communicator_);
    MPI_Comm_free(&world_ranks->failure_communicator_);
    world_ranks = nullptr;
  }
  MPI_Finalize();
}

#else  // one process

double Ranks::sum(double value) const {
  return value;
}
void Ranks::sum(std::span<double>) const {}
void Ranks::sum(std::span<std::int64_t>) const {}
double Ranks::min(double value) const {
  return value;
}
double Ranks::max(double value) const {
  return value;
}
std::int64_t Ranks::max(std::int64_t value) const {
  return value;
}
std::int64_t Ranks::exclusive_prefix_sum(std::int64_t) const {
  return 0;
}

std::vector<std::byte> Ranks::exchange(int to, std::span<const std::byte> bytes, int from) const {
  if (to < 0 && from < 0) return {};
  if (to == 0 && from == 0) return {bytes.begin(), bytes.end()};
  throw Error("Ranks::exchange: rank {} → {} on one process", from, to);
}

std::vector<std::vector<std::byte>> Ranks::all_to_all(
    const std::vector<std::vector<std::byte>>& outgoing) const {
  if (outgoing.size() != 1)
    throw Error("Ranks::all_to_all: {} buffers for 1 rank", outgoing.size());
  return outgoing;
}

std::vector<std::byte> Ranks::gather_to_root(std::span<const std::byte> bytes) const {
  return {bytes.begin(), bytes.end()};
}

std::string Ranks::broadcast(std::string text) const {
  return text;
}
void Ranks::barrier() const {}

std::optional<std::string> Ranks::first_problem(const std::optional<std::string>& local) const {
  return local;
}

int Ranks::fail(const std::string& program, const std::string& message) const {
  fmt::print(stderr, "{}: error: {}\n", program, message);
  return 1;
}

std::optional<std::string> Ranks::first_problem_within(const std::optional<std::string>& local,
                                                       double) const {
  return local;
}
void Ranks::remove_on_abort(const std::string&) {}
void Ranks::keep_on_abort(const std::string&) {}

RankSession::RankSession(int&, char**&) {}
RankSession::~RankSession() = default;

#endif

void Ranks::together(const std::function<void()>& work) const {
  if (!distributed()) return work();
  std::optional<std::string> problem;
  try {
    work();
  } catch (const std::bad_alloc&) {
    problem = "out of memory";
  } catch (const std::exception& e) {
    problem = e.what();
  }
  if (const auto first = first_problem(problem)) throw Error("{}", *first);
}

int run_main_on_ranks(const std::string& program, const std::function<void()>& body) {
  const Ranks& ranks = Ranks::world();
#if SLIDE_MPI
  program_name = program;
#endif
  try {
    body();
    return 0;
  } catch (const std::bad_alloc&) {
    return end_if_library_damaged(ranks.fail(program, "out of memory"));
  } catch (const std::exception& e) {
    return end_if_library_damaged(ranks.fail(program, printable_line(e.what())));
  }
}

}  // namespace slide
