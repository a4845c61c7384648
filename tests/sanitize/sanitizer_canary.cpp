// Built only by the sanitize preset (tests/sanitize/CMakeLists.txt): a program with one
// deliberate bug per command-line argument, so that canary_test.sh can check that each
// kind of report (AddressSanitizer, LeakSanitizer, UBSan) ends a program with the exit
// status the sanitize preset chooses and a report on stderr. `none` runs no bug.
#include <climits>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace {

// Volatile, so that the compiler can neither see the bugs at compile time nor drop them.
volatile int four = 4;
volatile int near_max = INT_MAX;
void* volatile kept = nullptr;

int heap_overflow() {
  const int n = four;
  int* values = new int[static_cast<unsigned>(n)]();
  values[n] = 1;  // one past the end
  const int first = values[0];
  delete[] values;
  return first;
}

int use_after_free() {
  int* values = new int[static_cast<unsigned>(four)]();
  delete[] values;
  return values[1];
}

int signed_overflow() {
  const int largest = near_max;
  return largest + four;
}

int leak() {
  kept = std::malloc(64);
  kept = nullptr;  // the only pointer to the block is gone
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  const char* bug = argc > 1 ? argv[1] : "none";
  int result = 0;
  if (std::strcmp(bug, "heap-overflow") == 0) result = heap_overflow();
  if (std::strcmp(bug, "use-after-free") == 0) result = use_after_free();
  if (std::strcmp(bug, "signed-overflow") == 0) result = signed_overflow();
  if (std::strcmp(bug, "leak") == 0) result = leak();
  std::printf("%s: %d\n", bug, result);
  return 0;
}
