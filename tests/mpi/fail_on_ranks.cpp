// run_main_on_ranks' two error paths (common/base/ranks.hpp), for failure_test.sh:
//   fail_on_ranks all   every rank throws: the root prints the one line, all exit 1;
//   fail_on_ranks one   rank 1 throws while the others wait in a collective it never
//                       joins: it prints its line with its rank and ends every rank.
//   fail_on_ranks library FILE
//                       rank 1's call into a library fails while rank 0 waits inside
//                       that library's own collective (parallel HDF5 after a full disk):
//                       first_problem_within lets rank 1 wait 1 s, then it prints its
//                       line, removes FILE (a temporary remove_on_abort names) and ends
//                       every rank.
#include <fstream>
#include <string>

#include <mpi.h>

#include "common/base/error.hpp"
#include "common/base/ranks.hpp"

int main(int argc, char** argv) {
  using namespace slide;
  const RankSession session(argc, argv);
  const std::string mode = argc > 1 ? argv[1] : "";
  return run_main_on_ranks("fail_on_ranks", [&] {
    const Ranks& ranks = Ranks::world();
    if (mode == "all") throw Error("every rank's failure");
    if (mode == "one" && ranks.rank() == 1) throw Error("rank 1's own failure");
    if (mode == "library" && argc > 2) {
      const std::string file = argv[2];
      if (ranks.root()) std::ofstream(file) << "a temporary being written\n";
      ranks.barrier();
      Ranks::remove_on_abort(file);
      // The library's own communicator, as parallel HDF5 keeps one per file.
      MPI_Comm library = MPI_COMM_NULL;
      MPI_Comm_dup(ranks.communicator(), &library);
      if (ranks.rank() != 1) MPI_Barrier(library);  // waits for rank 1 for ever
      const auto problem = ranks.first_problem_within(
          ranks.rank() == 1 ? std::optional<std::string>("the library's call failed")
                            : std::nullopt,
          1.0);
      if (problem) throw Error("{}", *problem);
    }
    ranks.barrier();  // in "one", the ranks but 1 wait here until the abort
  });
}
