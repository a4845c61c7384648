#include "common/io/atomic_file.hpp"

#include <fstream>
#include <system_error>

#include <unistd.h>

#include "common/base/error.hpp"

namespace slide {

void write_atomically(const std::filesystem::path& target,
                      const std::function<void(const std::filesystem::path&)>& write) {
  namespace fs = std::filesystem;
  const fs::path folder = target.has_parent_path() ? target.parent_path() : fs::path(".");
  std::error_code ec;
  fs::create_directories(folder, ec);
  if (ec)
    throw Error("{}: cannot create folder {}: {}", target.string(), folder.string(), ec.message());
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

void write_text_atomically(const std::filesystem::path& target, std::string_view text) {
  write_atomically(target, [&](const std::filesystem::path& temporary) {
    std::ofstream out(temporary, std::ios::binary);
    out.write(text.data(), static_cast<std::streamsize>(text.size()));
    out.close();
    if (!out) throw Error("{}: write failed", target.string());
  });
}

}  // namespace slide
