// The command-line tests run the programs as a user's shell would: a fresh folder per
// test, the program's stdout and stderr captured to files in it, files read back whole.
// A sanitizer report on the program's stderr (the sanitize build, tools/sanitize.sh)
// fails the test even where a non-zero exit is what the test expects.
#pragma once

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <sys/wait.h>

namespace slide::testing {

/// An emptied (or new) folder for one test's files.
inline std::filesystem::path fresh_folder(const std::filesystem::path& folder) {
  std::filesystem::remove_all(folder);
  std::filesystem::create_directories(folder);
  return folder;
}

inline std::string read_text(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

/// Writes `text` to `path`, creating its folder.
inline void write_file(const std::filesystem::path& path, const std::string& text) {
  std::filesystem::create_directories(path.parent_path());
  std::ofstream(path) << text;
}

/// True when `err` holds a report of AddressSanitizer, LeakSanitizer or UBSan.
inline bool has_sanitizer_report(const std::string& err) {
  for (const char* mark :
       {"ERROR: AddressSanitizer", "ERROR: LeakSanitizer", ": runtime error: "}) {
    if (err.find(mark) != std::string::npos) return true;
  }
  return false;
}

struct ProgramRun {
  int status = -1;  ///< the exit code; -1 when the program did not exit normally
  std::string out;
  std::string err;
};

/// Runs `command` (a program and its arguments) through the shell with stdout and stderr
/// captured in `folder`/stdout.txt and `folder`/stderr.txt.
inline ProgramRun run_program(const std::string& command, const std::filesystem::path& folder) {
  const std::filesystem::path out = folder / "stdout.txt", err = folder / "stderr.txt";
  const std::string line = command + " > " + out.string() + " 2> " + err.string();
  const int status = std::system(line.c_str());
  ProgramRun run{WIFEXITED(status) ? WEXITSTATUS(status) : -1, read_text(out), read_text(err)};
  if (has_sanitizer_report(run.err))
    ADD_FAILURE() << "sanitizer report from " << command << "\n" << run.err;
  return run;
}

}  // namespace slide::testing
