// Crash-safe file output: write to a temporary name in the target's folder, then rename.
// A reader (or a Makefile) never sees a half-written checkpoint, CSV or report, and an
// existing file stays intact when the writer fails.
#pragma once

#include <cstddef>
#include <filesystem>
#include <functional>
#include <string_view>

#include "common/base/ranks.hpp"

namespace slide {

/// Calls `write(temporary_path)` and renames the result onto `target`. Creates the
/// target's folder when needed. If `write` throws, the temporary file is removed and the
/// exception propagates; `target` is untouched.
/// `bytes`, about the file's size (0: not known), is checked against the folder's free
/// space first: a file that cannot fit is refused before it is begun (HDF5 1.10 left a
/// file whose close failed on a full disk in a state that crashed the program at exit).
void write_atomically(const std::filesystem::path& target,
                      const std::function<void(const std::filesystem::path&)>& write,
                      double bytes = 0.0);

/// write_atomically for a file every rank writes together (collective): one temporary
/// name for all (the root's), renamed by the root once every rank is done; every rank
/// throws the same Error when the rename fails. `bytes`, about the file's size (0: not
/// known), is checked against the folder's free space first, and a file that cannot fit
/// is refused on every rank before it is begun: a full disk met inside a shared write
/// can leave a rank waiting in parallel HDF5 (then the failing rank ends the job after a
/// grace period, removing the temporary: Ranks::remove_on_abort). On one rank:
/// write_atomically.
void write_atomically_on_ranks(const std::filesystem::path& target, const Ranks& ranks,
                               const std::function<void(const std::filesystem::path&)>& write,
                               double bytes = 0.0);

/// Writes two files that belong together (a particle file and its report) so that
/// `main` never stands beside a `companion` of another run: both are written under
/// temporary names; then the former `main` is removed, `companion` renamed into place,
/// and `main` last. A failure while writing leaves both former files; a kill between the
/// renames leaves no `main`, which a pipeline (Make) then builds again.
void write_pair_atomically(const std::filesystem::path& companion,
                           const std::function<void(const std::filesystem::path&)>& write_companion,
                           const std::filesystem::path& main,
                           const std::function<void(const std::filesystem::path&)>& write_main);

/// Writes `text` to `target` atomically.
void write_text_atomically(const std::filesystem::path& target, std::string_view text);

/// Removes the temporaries a killed writer left in `folder` (not its subfolders): the
/// hidden files `.<name>.tmp-<pid>` of write_atomically whose process no longer runs.
/// Those of live processes (another run writing into the same folder) stay. Returns how
/// many were removed; a missing folder has none.
std::size_t remove_stale_temporaries(const std::filesystem::path& folder);

}  // namespace slide
