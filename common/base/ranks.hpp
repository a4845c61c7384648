// The processes of one run: MPI ranks in the MPI build (cmake -DSLIDE_MPI=ON), one
// process otherwise. Code that may run on several processes (mpm-solve, the collective
// checkpoint) talks to its peers through this class only, so that the serial build has
// the same code path with every operation a no-op on one process.
//
// Every operation named collective must be called by every rank, in the same order.
// Byte buffers are the exchange unit: the callers pack trivially copyable rows.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <type_traits>
#include <vector>

#if SLIDE_MPI
#include <mpi.h>
#endif

namespace slide {

/// Rows [first, end) of a set of rows.
struct RowSpan {
  std::size_t first = 0;
  std::size_t end = 0;
  std::size_t count() const { return end - first; }
  /// How many of the last `tail` rows of the set's n lie in this span (its last ones).
  std::size_t last_rows_within(std::size_t n, std::size_t tail) const;
};

/// Part `index` of `parts` of a set of rows that processes split among them (each MPI
/// rank its own: docs/parallel.md): rows [⌊index·n/parts⌋, ⌊(index + 1)·n/parts⌋),
/// contiguous and in order, all of them together.
struct Part {
  int index = 0;
  int parts = 1;
  /// Throws Error unless 0 ≤ index < parts.
  RowSpan rows(std::size_t n) const;
};

class Ranks {
 public:
  /// All processes of this program (MPI_COMM_WORLD; one process in the serial build).
  /// RankSession must be alive.
  static Ranks& world();
  /// One process alone (what world() is without a session, and in the serial build).
  static Ranks& single();

  int rank() const { return rank_; }
  int size() const { return size_; }
  bool root() const { return rank_ == 0; }
  bool distributed() const { return size_ > 1; }
  /// This rank's part of a set of rows split among the ranks.
  Part part() const { return {rank_, size_}; }
  /// Ranks on this rank's machine (shared memory), this one included: they share its cores.
  int on_this_machine() const { return machine_size_; }

  // Reductions (collective): every rank gets the result.
  double sum(double value) const;
  void sum(std::span<double> values) const;
  void sum(std::span<std::int64_t> values) const;
  double min(double value) const;
  double max(double value) const;
  std::int64_t max(std::int64_t value) const;
  /// Σ of `value` over the ranks below this one (0 on rank 0).
  std::int64_t exclusive_prefix_sum(std::int64_t value) const;

  /// Sends `bytes` to rank `to` and receives from rank `from` (either −1: none) in one
  /// step; returns what was received. Collective between the pairs only.
  std::vector<std::byte> exchange(int to, std::span<const std::byte> bytes, int from) const;
  /// Rank r sends outgoing[r] to each r (outgoing.size() = size()); returns what every
  /// rank sent to this one, in rank order. Collective.
  std::vector<std::vector<std::byte>> all_to_all(
      const std::vector<std::vector<std::byte>>& outgoing) const;
  /// The buffers of every rank, concatenated in rank order, on the root; empty on the
  /// others. Collective.
  std::vector<std::byte> gather_to_root(std::span<const std::byte> bytes) const;
  /// The root's string on every rank. Collective.
  std::string broadcast(std::string text) const;
  void barrier() const;

  /// The problem of the lowest rank that has one, on every rank (nothing when no rank
  /// has one): a check made on each rank's share becomes one decision. Collective.
  std::optional<std::string> first_problem(const std::optional<std::string>& local) const;
  /// first_problem after a call into a library's own collectives (parallel HDF5): there a
  /// rank that failed may have left a peer waiting inside the library, never to reach this
  /// point. A rank with a problem waits for its peers at most `grace_seconds`, then ends
  /// every rank with its message (MPI_Abort, after removing the files remove_on_abort
  /// names); a rank without one waits as long as it takes (every rank, for an infinite
  /// grace: first_problem). Collective.
  std::optional<std::string> first_problem_within(const std::optional<std::string>& local,
                                                  double grace_seconds = 10.0) const;

  /// The files to remove when a rank ends the job with MPI_Abort, which runs no
  /// destructor on any rank: the temporary of a shared file being written, the output
  /// folder's lock. keep_on_abort takes a path off the list.
  static void remove_on_abort(const std::string& path);
  static void keep_on_abort(const std::string& path);

  /// Runs `work` on this rank; when it throws on any rank, every rank throws an Error
  /// with the lowest failing rank's message, here. Collective, called by every rank at
  /// the same point after the last exchange inside `work`: a write that fails on one rank
  /// (a full disk) then ends every rank at one place, instead of leaving its peers waiting
  /// in the next exchange while it closes a shared file (a hang). On one process: `work`.
  void together(const std::function<void()>& work) const;

  /// Typed views of the byte exchanges, for trivially copyable rows.
  template <class T>
  static std::span<const std::byte> bytes_of(std::span<const T> values) {
    static_assert(std::is_trivially_copyable_v<T>);
    return std::as_bytes(values);
  }
  template <class T>
  static std::vector<T> values_of(std::span<const std::byte> bytes) {
    static_assert(std::is_trivially_copyable_v<T>);
    std::vector<T> values(bytes.size() / sizeof(T));
    if (!values.empty()) std::memcpy(values.data(), bytes.data(), values.size() * sizeof(T));
    return values;
  }

#if SLIDE_MPI
  MPI_Comm communicator() const {
    return communicator_;
  }
#endif

 private:
  friend class RankSession;
  Ranks() = default;
  int rank_ = 0;
  int size_ = 1;
  int machine_size_ = 1;
#if SLIDE_MPI
  MPI_Comm communicator_ = MPI_COMM_NULL;
  MPI_Comm failure_communicator_ = MPI_COMM_NULL;  ///< Ranks::fail's own, apart from the run's
#endif
  friend int run_main_on_ranks(const std::string&, const std::function<void()>&);
  /// The error path of run_main_on_ranks (see there).
  int fail(const std::string& program, const std::string& message) const;
};

/// MPI_Init_thread … MPI_Finalize for the lifetime of main (nothing in the serial build).
class RankSession {
 public:
  RankSession(int& argc, char**& argv);
  ~RankSession();
  RankSession(const RankSession&) = delete;
  RankSession& operator=(const RankSession&) = delete;
};

/// run_main (common/base/program.hpp) for a program that runs on several ranks. An
/// exception becomes the one-line error and status 1 without a deadlock: when every
/// rank fails (bad input, an instability the ranks agreed on), only the root prints
/// and all return 1; when one rank fails alone (its peers wait for it inside a step),
/// it prints its line and ends every rank (MPI_Abort, after which mpirun adds its own
/// notice). Needs a RankSession.
int run_main_on_ranks(const std::string& program, const std::function<void()>& body);

}  // namespace slide
