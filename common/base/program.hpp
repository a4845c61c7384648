// What every program's main shares: command-line parsing that reports a bad option in
// one line, and the translation of any exception into a one-line error on stderr and a
// non-zero exit status.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <string_view>

#include <CLI/CLI.hpp>

namespace slide {

/// OpenMP threads that sleep instead of spinning at the kernels' barriers. By
/// default libgomp spins some 300,000 times before a waiting thread sleeps; when another
/// process holds the core of the thread being waited for, the spinning burns the
/// timeslices that thread needs, and 2 threads on a loaded 2-core machine ran 3-8 times
/// slower than 1 (mpm/README.md, "Threads on a shared machine"). Unless the environment
/// chooses already (OMP_WAIT_POLICY or GOMP_SPINCOUNT), the program starts itself again,
/// once, with `omp_wait_setting` in its environment: libgomp reads its settings when it
/// loads, before main, so no call can change them later. Call first in main, before
/// anything else (MPI included); returns only when nothing is to change or the new start
/// failed (the program then runs as it is).
void prefer_yielding_threads(char** argv);
/// The setting prefer_yielding_threads adds to the environment: passive, the standard
/// policy (a waiting thread sleeps at once), which on the 2 cores each loaded by another
/// process kept 2 threads above 1 (5.5-5.8 M particle-steps/s against 4.0 M) where a
/// short spin (GOMP_SPINCOUNT=10000) did not (3.4-5.0 M), for 3 % on a quiet machine.
inline constexpr const char* omp_wait_setting = "OMP_WAIT_POLICY=passive";

/// "slide 0.1.0 (commit 2e5f598c1a2b)": the version and the commit the build was configured
/// from (cmake/SlideVersion.cmake); goes into every file's `producer` attribute with the
/// program name, and `--version` prints it.
std::string version_string();

/// Parses the command line. Returns an exit status when the program should stop now
/// (0 after --help or --version, 2 after a bad option, with a one-line message), or
/// nothing when it should go on.
///
/// --help prints `gnu_help`: the layout of the GNU coding standards ("Usage: PROGRAM
/// [OPTION]... CASE", what it does, the options as "-o, --output=TEXT" with their meaning
/// in a column, then the exit statuses and where the documentation is).
std::optional<int> parse_command_line(CLI::App& app, int argc, char** argv);

/// The help text of `app` (or of the subcommand the command line selected) in the GNU
/// layout, lines within 80 columns.
std::string gnu_help(const CLI::App& app);

/// Option checks with a readable message ("must be > 0"); CLI11's PositiveNumber names
/// the range of the type instead, a 309-digit number for a double.
CLI::Validator positive_number();
CLI::Validator non_negative_number();

/// `text` as one line of valid UTF-8 for a terminal: each byte that is not part of a
/// well-formed UTF-8 sequence, and each control character (line breaks included),
/// becomes a visible escape such as \xff or \n. Names read from damaged files can
/// hold any bytes; an error message that quotes them must still be one readable line.
std::string printable_line(std::string_view text);

/// Runs `body`; an exception becomes "program: error: message" on stderr and status 1
/// (the message passed through printable_line).
int run_main(const std::string& program, const std::function<void()>& body);

/// For a library wrapper whose library is left in a state its own termination at exit
/// would crash on (HDF5 1.10 after a file's close failed on a full disk: a segfault in
/// MPI_Finalize). The error paths of run_main and run_main_on_ranks then end the process
/// right after their one line, with its status, without that termination.
void mark_library_damaged();
/// The status, after the process's streams are flushed: the process ends here when a
/// library was marked damaged.
int end_if_library_damaged(int status);

}  // namespace slide
