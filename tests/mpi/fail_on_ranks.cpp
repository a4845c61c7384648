// run_main_on_ranks' two error paths (common/base/ranks.hpp), for failure_test.sh:
//   fail_on_ranks all   every rank throws: the root prints the one line, all exit 1;
//   fail_on_ranks one   rank 1 throws while the others wait in a collective it never
//                       joins: it prints its line with its rank and ends every rank.
#include <string>

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
    ranks.barrier();  // in "one", the ranks but 1 wait here until the abort
  });
}
