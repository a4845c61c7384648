// One run per output folder: a run holds OUT/.slide-lock while it writes there, so that a
// second run into the same folder is refused at once, with one line naming the first,
// instead of both writing and mixing their files. The lock records the holder's pid, its
// start time and the host; a lock whose process is gone (a run killed with -9) is taken
// over, a pid reused by another process is told apart by its start time.
#pragma once

#include <filesystem>
#include <string>

namespace slide::run {

class OutputLock {
 public:
  /// Takes the lock of `folder` (which exists). Error naming the folder and the run that
  /// holds it when a live process does.
  /// The lock file's name in the folder.
  static constexpr const char* file_name = ".slide-lock";
  explicit OutputLock(const std::filesystem::path& folder);
  ~OutputLock();
  OutputLock(const OutputLock&) = delete;
  OutputLock& operator=(const OutputLock&) = delete;

  /// Whether the lock of a run that is gone was taken over (for the log).
  bool took_over() const { return took_over_; }
  const std::filesystem::path& file() const { return file_; }

 private:
  std::filesystem::path file_;
  std::string mine_;
  bool took_over_ = false;
};

/// "pid start host": this process's mark in a lock file.
std::string this_process_mark();
/// Whether `mark` names a process of this host that still runs (the same pid and start
/// time); a mark that does not parse names none.
bool process_alive(const std::string& mark);

}  // namespace slide::run
