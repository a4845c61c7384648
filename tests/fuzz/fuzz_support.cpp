// The shared part of the fuzz drivers (fuzz_support.hpp).
#include "tests/fuzz/fuzz_support.hpp"

#include <cstdlib>
#include <fstream>
#include <map>
#include <memory>
#include <string>
#include <system_error>

#include <hdf5.h>
#include <unistd.h>

namespace slide::fuzz {

namespace fs = std::filesystem;

namespace {

fs::path scratch_root() {
  if (const char* root = std::getenv("SLIDE_FUZZ_SCRATCH"); root != nullptr && *root != '\0') {
    return root;
  }
  std::error_code ec;
  if (fs::is_directory("/dev/shm", ec)) return "/dev/shm";
  return fs::temp_directory_path();
}

// A copy of stderr taken before main, that is before libFuzzer or the seeded driver
// close or redirect descriptor 2.
const int original_stderr = ::dup(2);

void remove_scratch_folder() {
  std::error_code ec;
  fs::remove_all(scratch_folder(), ec);
}

[[noreturn]] void finding(std::string_view what, std::string_view problem) {
  report("fuzz finding: " + std::string(what) + ": " + std::string(problem));
  std::abort();
}

std::uint64_t accepted = 0;

}  // namespace

void report(std::string_view line) {
  std::string text(line);
  text += '\n';
  const int fd = original_stderr >= 0 ? original_stderr : 2;
  for (std::size_t written = 0; written < text.size();) {
    const ssize_t n = ::write(fd, text.data() + written, text.size() - written);
    if (n <= 0) return;
    written += static_cast<std::size_t>(n);
  }
}

void note_rejection(std::string_view message) {
  static const bool show = std::getenv("SLIDE_FUZZ_SHOW_ERRORS") != nullptr;
  if (show) report("rejected: " + std::string(message));
}

fs::path scratch_folder_of(int pid) {
  return scratch_root() / ("slide-fuzz-" + std::to_string(pid));
}

const fs::path& scratch_folder() {
  // Named by the process id: libFuzzer's fork mode and parallel test runs each get their own.
  static const fs::path folder = [] {
    const fs::path path = scratch_folder_of(::getpid());
    fs::create_directories(path);
    return path;
  }();
  static const bool cleanup_registered = [] { return std::atexit(remove_scratch_folder) == 0; }();
  (void)cleanup_registered;
  return folder;
}

fs::path write_input(std::span<const std::uint8_t> data, std::string_view name) {
  const fs::path path = scratch_folder() / name;
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(data.data()), static_cast<std::streamsize>(data.size()));
  out.close();
  if (!out) finding("write_input", "cannot write the input to " + path.string());
  return path;
}

fs::path output_folder() {
  return scratch_folder() / "out";
}

void ensure_no_outputs(std::string_view what) {
  std::error_code ec;
  if (fs::exists(output_folder(), ec)) {
    finding(what, "a run that only checks its inputs created " + output_folder().string());
  }
}

void ensure_hdf5_closed(std::string_view what) {
  // HDF5 may not be initialised yet (an input rejected before any file was opened): the
  // count would initialise it, so first keep its shutdown out of exit as the readers do
  // (common/io/hdf5_file.cpp; a no-op once the library runs).
  static const bool no_shutdown = [] {
    H5dont_atexit();
    return true;
  }();
  (void)no_shutdown;
  const ssize_t open_objects = H5Fget_obj_count(H5F_OBJ_ALL, H5F_OBJ_ALL);
  if (open_objects > 0) {
    finding(what, std::to_string(open_objects) + " HDF5 object(s) still open after the input");
  }
}

void finish_hdf5_input(std::string_view what) {
  ensure_hdf5_closed(what);
  if (H5close() < 0) finding(what, "H5close failed");
}

const Case& fixture_case(std::string_view name) {
  static std::map<std::string, std::unique_ptr<const Case>, std::less<>> cases;
  const auto found = cases.find(name);
  if (found != cases.end()) return *found->second;
  const fs::path file = fs::path(SLIDE_SOURCE_DIR) / "tests/fuzz/cases" / name / "case.toml";
  try {
    auto loaded = std::make_unique<const Case>(load_case(file));
    return *cases.emplace(std::string(name), std::move(loaded)).first->second;
  } catch (const Error& error) {
    finding("fixture case", error.what());
  }
}

const Logger& quiet_logger() {
  static const Logger logger("fuzz", true);
  return logger;
}

void note_accepted() {
  ++accepted;
}

std::uint64_t accepted_count() {
  return accepted;
}

}  // namespace slide::fuzz
