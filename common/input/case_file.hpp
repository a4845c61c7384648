// The case file: one `cases/<name>/case.toml` drives all three programs (geometry,
// materials, FE stages, transfer, MPM, metrics). The reader is strict: an unknown key, a
// missing required key, a wrong type or an impossible value is an Error of the form
//   case.toml:12: fem.end_time = -1 is not admissible (expected > 0 s)
// naming the file, the line and the dotted key. The file format is documented key by
// key in common/input/case-file.md; every case in cases/ is a commented example.
#pragma once

#include <array>
#include <cstddef>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "common/base/types.hpp"
#include "common/geometry/element.hpp"
#include "common/geometry/mesh.hpp"
#include "common/physics/algorithms.hpp"
#include "common/physics/material.hpp"
#include "common/settings/fem_spec.hpp"
#include "common/settings/mesh_spec.hpp"
#include "common/settings/metrics_spec.hpp"
#include "common/settings/mpm_spec.hpp"
#include "common/settings/transfer_spec.hpp"

namespace slide {

// ----------------------------------------------------------------------------- case

struct Case {
  std::filesystem::path file;  ///< the case file it was read from
  std::string name;
  std::string description;
  /// g, m/s²: (0, −9.81) (docs/method.md §2), or turned by [case] gravity_angle.
  Vec2 gravity = gravity_vector();
  MaterialTable materials;
  MeshSpec mesh;
  FemSpec fem;
  TransferSpec transfer;
  MpmSpec mpm;
  MetricsSpec metrics;
  std::optional<OpenSeesImportSpec> opensees;  ///< [opensees], when the case has it

  /// Index of the material called `name`; throws Error when there is none.
  std::int32_t material_index(std::string_view name) const;
};

/// The largest case file load_case reads: 4 MiB (the cases are a few kB; a Gmsh mesh
/// lives in its own file).
inline constexpr std::size_t max_case_file_bytes = std::size_t{4} << 20;

/// Reads and validates a case file; throws Error (file:line: key: problem) on any fault.
Case load_case(const std::filesystem::path& path);
/// Same, from text (tests); `source_name` stands in for the file name in messages.
Case parse_case(std::string_view text, const std::filesystem::path& source_name);

}  // namespace slide
