#include "common/run/output_lock.hpp"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <optional>
#include <sstream>

#include <fcntl.h>
#include <fmt/format.h>
#include <unistd.h>

#include "common/base/error.hpp"

namespace slide::run {

namespace {

/// The start time of process `pid` in clock ticks since boot (field 22 of
/// /proc/<pid>/stat), or none when there is no such process or it has ended: a process
/// killed with -9 stays a zombie (state Z) until its parent reaps it, and one whose
/// launcher (mpirun) was killed too may stay one for long; it writes nothing more.
std::optional<unsigned long long> process_start(long pid) {
  std::ifstream stat(fmt::format("/proc/{}/stat", pid));
  std::string text;
  if (!stat || !std::getline(stat, text)) return std::nullopt;
  // The command name (field 2) is in parentheses and may hold spaces: count after it.
  const auto close = text.rfind(')');
  if (close == std::string::npos) return std::nullopt;
  std::istringstream fields(text.substr(close + 1));
  std::string field;
  for (int i = 3; i <= 22 && fields >> field; ++i) {
    if (i == 3 && (field == "Z" || field == "X")) return std::nullopt;
    if (i == 22) return std::stoull(field);
  }
  return std::nullopt;
}

std::string host_name() {
  char name[256] = {};
  return ::gethostname(name, sizeof name - 1) == 0 ? std::string(name) : std::string("unknown");
}

struct Mark {
  long pid = 0;
  unsigned long long start = 0;
  std::string host;
};

std::optional<Mark> parse(const std::string& text) {
  std::istringstream in(text);
  Mark m;
  if (!(in >> m.pid >> m.start >> m.host) || m.pid <= 0) return std::nullopt;
  return m;
}

std::string read_all(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

/// Creates `file` with `mark` unless it exists (atomic: O_EXCL). False when it exists.
bool create_exclusive(const std::filesystem::path& file, const std::string& mark) {
  const int fd = ::open(file.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
  if (fd < 0) {
    if (errno == EEXIST) return false;
    throw Error("{}: cannot create the output lock: {}", file.string(), std::strerror(errno));
  }
  const bool written = ::write(fd, mark.data(), mark.size()) == static_cast<ssize_t>(mark.size());
  const bool closed = ::close(fd) == 0;
  if (!written || !closed) {
    ::unlink(file.c_str());
    throw Error("{}: cannot write the output lock (disk full?)", file.string());
  }
  return true;
}

}  // namespace

std::string this_process_mark() {
  const long pid = ::getpid();
  return fmt::format("{} {} {}\n", pid, process_start(pid).value_or(0), host_name());
}

bool process_alive(const std::string& text) {
  const auto mark = parse(text);
  if (!mark) return false;
  if (mark->host != host_name()) return true;  // another machine's: not ours to judge
  const auto start = process_start(mark->pid);
  return start && *start == mark->start;
}

OutputLock::OutputLock(const std::filesystem::path& folder)
    : file_(folder / file_name), mine_(this_process_mark()) {
  for (int attempt = 0; attempt < 2; ++attempt) {
    if (create_exclusive(file_, mine_)) return;
    const std::string holder = read_all(file_);
    if (process_alive(holder)) {
      const auto mark = parse(holder);
      throw Error(
          "{}: another run (pid {} on {}) is writing there: wait for it to end, or give "
          "another output folder",
          folder.string(), mark->pid, mark->host);
    }
    // A run killed before it could remove its lock (or a damaged lock): take it over.
    std::error_code ec;
    std::filesystem::remove(file_, ec);
    took_over_ = true;
  }
  throw Error("{}: cannot take the output lock {}", folder.string(), file_.string());
}

OutputLock::~OutputLock() {
  // Only our own: a run that took over a lock it judged stale would else lose it.
  if (read_all(file_) == mine_) ::unlink(file_.c_str());
}

}  // namespace slide::run
