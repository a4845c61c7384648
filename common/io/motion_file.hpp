// A base acceleration record as users keep them (docs/method.md §8): a text file of two
// columns, time (s) and acceleration, separated by spaces, tabs or one comma; blank lines
// and everything after '#' ignored. The case states the unit of the second column (m/s²
// or g, converted with g = 9.81 m/s²). Times must start at or after 0 and increase.
#pragma once

#include <filesystem>

#include "common/physics/ground_motion.hpp"

namespace slide {

/// The largest motion file read: 64 MiB (a 100 s record at 1 kHz is about 2 MB).
inline constexpr std::uintmax_t max_motion_file_bytes = std::uintmax_t{64} << 20;

/// Reads the record, each acceleration multiplied by `scale` (1 for m/s², 9.81 for g).
/// Throws Error "file:line: problem" on any fault.
AccelerationRecord read_motion_file(const std::filesystem::path& path, double scale);

}  // namespace slide
