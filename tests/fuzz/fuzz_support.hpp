// What the five fuzz drivers share (tests/fuzz/README.md): a scratch folder of their
// own for the files the readers take by path, the fixture cases the checkpoints are
// checked against, and the rule of a driver: a slide::Error is a clean rejection,
// anything else that escapes, a signal, a sanitizer report or a hang is a finding.
//
// Each driver implements libFuzzer's entry point
//   extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);
// and is linked either with libFuzzer (clang, -DSLIDE_FUZZ=ON) or with the seeded
// mutation driver of tests/fuzz/seeded/ (any compiler, the default test suite).
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <span>
#include <string_view>

#include "common/base/error.hpp"
#include "common/base/log.hpp"
#include "common/input/case_file.hpp"

namespace slide::fuzz {

/// This process's scratch folder, created on first use and removed at exit: a folder
/// named after the process id under $SLIDE_FUZZ_SCRATCH, else under /dev/shm (memory,
/// no disk wear), else under the system's temporary folder.
const std::filesystem::path& scratch_folder();

/// Writes the input to `name` in the scratch folder (replacing the previous input) and
/// returns its path.
std::filesystem::path write_input(std::span<const std::uint8_t> data, std::string_view name);

/// Where the programs would write their outputs: a folder of the scratch folder that
/// a check of the inputs alone must never create (ensure_no_outputs).
std::filesystem::path output_folder();
/// Aborts (a finding) when a run that only checks its inputs wrote anything.
void ensure_no_outputs(std::string_view what);

/// Aborts (a finding) when HDF5 still has a file or object open: every reader must
/// close what it opened, also on its error paths, or the next input would read a stale
/// file and the process would run out of handles.
void ensure_hdf5_closed(std::string_view what);

/// ensure_hdf5_closed, then shuts the HDF5 library down (H5close; the next call starts it
/// afresh): every input starts from a library without the caches and free lists of the
/// inputs before it, as every program run does, so that a finding reproduces from its
/// input alone.
void finish_hdf5_input(std::string_view what);

/// The fixture case of a driver, read once: tests/fuzz/cases/<name>/case.toml.
const Case& fixture_case(std::string_view name);

/// The logger the drivers pass to the programs' code: info silenced; warnings still go
/// to stderr (libFuzzer runs with -close_fd_mask=3, the seeded driver without output).
const Logger& quiet_logger();

/// Reports `message` when SLIDE_FUZZ_SHOW_ERRORS is set (accepts).
void note_rejection(std::string_view message);

/// Runs `step`; a slide::Error is a clean rejection (false), anything else propagates.
/// With SLIDE_FUZZ_SHOW_ERRORS set in the environment each rejection is reported.
template <typename Step>
bool accepts(Step&& step) {
  try {
    step();
    return true;
  } catch (const Error& error) {
    note_rejection(error.what());
    return false;
  }
}

/// Writes `line` and a newline to the process's original stderr, which stays open when
/// libFuzzer (-close_fd_mask) or the seeded driver silence file descriptor 2.
void report(std::string_view line);

/// The scratch folder of process `pid`: the seeded driver removes those of its children
/// that died on a finding.
std::filesystem::path scratch_folder_of(int pid);

/// Counts the inputs a driver accepted whole (every step without an Error), for the
/// seeded driver's check that the valid seeds reach the end of the read path.
void note_accepted();
std::uint64_t accepted_count();

}  // namespace slide::fuzz
