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
