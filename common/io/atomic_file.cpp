#include "common/io/atomic_file.hpp"

#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <optional>
#include <string>
#include <string_view>
#include <system_error>

#include <fcntl.h>
#include <sys/types.h>
#include <unistd.h>

#include "common/base/error.hpp"

namespace slide {

namespace {

/// The refusal of a file of about `bytes` that the disk of `folder` has no room for.
std::optional<std::string> no_room(const std::filesystem::path& target,
                                   const std::filesystem::path& folder, double bytes) {
  std::error_code ec;
  const std::filesystem::space_info space = std::filesystem::space(folder, ec);
  const auto available = static_cast<double>(space.available);
  // 10 % of the estimate is left to chance: it counts the arrays a file stores, which
  // their layout may shrink or grow a little, and a file refused must not fit.
  if (ec || !(0.9 * bytes > available)) return std::nullopt;
  return fmt::format("{}: cannot write: about {:.3g} MB, the disk has {:.3g} MB free ({})",
                     target.string(), bytes / 1e6, available / 1e6, std::strerror(ENOSPC));
}

}  // namespace

void write_atomically(const std::filesystem::path& target,
                      const std::function<void(const std::filesystem::path&)>& write,
                      double bytes) {
  namespace fs = std::filesystem;
  const fs::path folder = target.has_parent_path() ? target.parent_path() : fs::path(".");
  std::error_code ec;
  fs::create_directories(folder, ec);
  if (ec)
    throw Error("{}: cannot create folder {}: {}", target.string(), folder.string(), ec.message());
  if (const auto refusal = no_room(target, folder, bytes)) throw Error("{}", *refusal);
  // Hidden, unique per process: two programs writing into one folder do not collide.
  const fs::path temporary =
      folder / fmt::format(".{}.tmp-{}", target.filename().string(), ::getpid());
  try {
    write(temporary);
  } catch (...) {
    fs::remove(temporary, ec);
    throw;
  }
  fs::rename(temporary, target, ec);
  if (ec) {
    std::error_code ignored;
    fs::remove(temporary, ignored);
    throw Error("{}: cannot rename the temporary file into place: {}", target.string(),
                ec.message());
  }
}

void write_atomically_on_ranks(const std::filesystem::path& target, const Ranks& ranks,
                               const std::function<void(const std::filesystem::path&)>& write,
                               double bytes) {
  if (!ranks.distributed()) return write_atomically(target, write, bytes);
  namespace fs = std::filesystem;
  const fs::path folder = target.has_parent_path() ? target.parent_path() : fs::path(".");
  std::string problem;
  if (ranks.root()) {
    std::error_code ec;
    fs::create_directories(folder, ec);
    if (ec) {
      problem = fmt::format("{}: cannot create folder {}: {}", target.string(), folder.string(),
                            ec.message());
    } else if (const auto refusal = no_room(target, folder, bytes)) {
      problem = *refusal;
    }
  }
  if (const auto agreed =
          ranks.first_problem(problem.empty() ? std::nullopt : std::optional(problem))) {
    throw Error("{}", *agreed);
  }
  const fs::path temporary = ranks.broadcast(
      (folder / fmt::format(".{}.tmp-{}", target.filename().string(), ::getpid())).string());
  Ranks::remove_on_abort(temporary.string());
  try {
    write(temporary);
  } catch (...) {
    Ranks::keep_on_abort(temporary.string());
    std::error_code ignored;
    if (ranks.root()) fs::remove(temporary, ignored);
    throw;
  }
  Ranks::keep_on_abort(temporary.string());
  ranks.barrier();  // every rank has closed the file
  if (ranks.root()) {
    std::error_code ec;
    fs::rename(temporary, target, ec);
    if (ec) {
      std::error_code ignored;
      fs::remove(temporary, ignored);
      problem = fmt::format("{}: cannot rename the temporary file into place: {}", target.string(),
                            ec.message());
    }
  }
  if (const auto agreed =
          ranks.first_problem(problem.empty() ? std::nullopt : std::optional(problem))) {
    throw Error("{}", *agreed);
  }
}

void write_pair_atomically(const std::filesystem::path& companion,
                           const std::function<void(const std::filesystem::path&)>& write_companion,
                           const std::filesystem::path& main,
                           const std::function<void(const std::filesystem::path&)>& write_main) {
  write_atomically(main, [&](const std::filesystem::path& temporary_main) {
    write_main(temporary_main);
    write_atomically(companion, [&](const std::filesystem::path& temporary_companion) {
      write_companion(temporary_companion);
      std::error_code ec;
      std::filesystem::remove(main, ec);
      if (ec) throw Error("{}: cannot replace: {}", main.string(), ec.message());
    });
  });
}

void write_text_atomically(const std::filesystem::path& target, std::string_view text) {
  // POSIX calls rather than a stream: a failed write or close then says why (errno: "No
  // space left on device"), where std::ofstream only says that it failed.
  write_atomically(target, [&](const std::filesystem::path& temporary) {
    const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd < 0) throw Error("{}: cannot create: {}", target.string(), std::strerror(errno));
    std::string_view rest = text;
    while (!rest.empty()) {
      const ssize_t written = ::write(fd, rest.data(), rest.size());
      if (written < 0 && errno == EINTR) continue;
      if (written <= 0) {
        const int error = written < 0 ? errno : ENOSPC;
        ::close(fd);
        throw Error("{}: cannot write: {}", target.string(), std::strerror(error));
      }
      rest.remove_prefix(static_cast<std::size_t>(written));
    }
    if (::close(fd) != 0) {
      throw Error("{}: cannot write: {}", target.string(), std::strerror(errno));
    }
  });
}

namespace {

/// True once process `pid` has ended: kill(pid, 0) fails with ESRCH (EPERM: it runs as
/// another user), or it is a zombie, killed and not yet reaped (state Z in
/// /proc/<pid>/stat: an MPI rank whose mpirun was killed too may stay one for long).
bool process_gone(pid_t pid) {
  if (::kill(pid, 0) != 0) return errno == ESRCH;
  std::FILE* stat = std::fopen(fmt::format("/proc/{}/stat", pid).c_str(), "r");
  if (stat == nullptr) return false;
  char text[512] = {};
  const std::size_t length = std::fread(text, 1, sizeof text - 1, stat);
  std::fclose(stat);
  const std::string_view line(text, length);
  const auto close = line.rfind(')');
  return close != std::string_view::npos && close + 2 < line.size() &&
         (line[close + 2] == 'Z' || line[close + 2] == 'X');
}

}  // namespace

std::size_t remove_stale_temporaries(const std::filesystem::path& folder) {
  namespace fs = std::filesystem;
  std::error_code ec;
  std::size_t removed = 0;
  for (const auto& entry : fs::directory_iterator(folder, ec)) {
    const std::string name = entry.path().filename().string();
    const auto mark = name.rfind(".tmp-");
    if (name.empty() || name[0] != '.' || mark == std::string::npos) continue;
    const std::string digits = name.substr(mark + 5);
    if (digits.empty() || digits.size() > 9 ||
        digits.find_first_not_of("0123456789") != std::string::npos) {
      continue;
    }
    const auto pid = static_cast<pid_t>(std::stol(digits));
    if (pid > 0 && process_gone(pid) && entry.is_regular_file(ec)) {
      if (fs::remove(entry.path(), ec)) ++removed;
    }
  }
  return removed;
}

}  // namespace slide
