// Import of 2D OpenSees models and their recorder output (tools/interop/README.md).
//
// The model comes from OpenSees's own JSON print (`print -JSON -file model.json`), of
// which only the "geometry" object is read: nodes {"name", "ndf", "crd"} and elements
// {"name", "type", "nodes", "material"}. The "properties" object is not read, because
// OpenSees prints some nDMaterials (PressureIndependMultiYield, PressureDependMultiYield)
// there as plain text, which makes the whole document invalid JSON; the materials come
// from the case file instead, mapped by OpenSees material tag.
//
// Element classes and what they become (one class per model):
//   FourNodeQuad        → quad4-2x2 (2×2 Gauss points, matched by place)
//   SSPquad, SSPquadUP  → quad4-1gp (one stress point at the centre)
//   Tri31               → tri3 (one point at the centroid)
// Classes the case lists in mesh.ignore_elements (e.g. "ZeroLength" dashpots) are
// skipped; any other class is an error. Nodes no kept element uses are dropped.
// The mesh's nodes and elements are numbered in increasing OpenSees tag order, the order
// the recorders must list them in. Node sets: `left`, `right` and `base`, the nodes on
// the left, right and bottom edges of the model's bounding box (the JSON carries no
// fix commands).
//
// Recorder files are OpenSees's text output with the `-time` column: one row per
// recorded step, the time first, then the values, separated by white space.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "common/geometry/mesh.hpp"
#include "common/physics/material.hpp"

namespace slide {

/// A model read from OpenSees's JSON print.
struct OpenSeesMesh {
  Mesh mesh;                               ///< nodes, elements, material ids, left/right/base
  std::string element_class;               ///< "FourNodeQuad", "SSPquad", "SSPquadUP", "Tri31"
  std::vector<std::int64_t> node_tags;     ///< per mesh node, increasing
  std::vector<std::int64_t> element_tags;  ///< per mesh element, increasing
  std::vector<int> node_dofs;              ///< per mesh node: ndf (3 for u–p nodes)
  /// Tags of every node of the JSON, increasing: the columns of a Node recorder that
  /// lists all nodes (`-nodeRange first last` or every tag), dropped nodes included.
  std::vector<std::int64_t> all_node_tags;
  /// Elements skipped by mesh.ignore_elements, per class.
  std::map<std::string, std::int64_t> ignored;
};

/// The element type an OpenSees element class becomes, or nothing for a class the
/// import does not read.
std::optional<ElementType> opensees_element_type(std::string_view element_class);

/// The element type of the model's continuum elements (the first class not ignored);
/// Error when the file cannot be read or holds no element the import reads.
ElementType read_opensees_element_type(const std::filesystem::path& path,
                                       const std::vector<std::string>& ignore_elements);

/// Reads the model. `material_of_tag` maps OpenSees nDMaterial tags to names of
/// `materials`. Throws Error (file, line where known, tag at fault) on invalid JSON, a
/// missing or mistyped field, a 3D node, an unknown or mixed element class, a node an
/// element names that the model does not have, an unmapped material tag, an element
/// inverted or of zero area (clockwise nodes), a crooked edge of the bounding box: the
/// faults validate_mesh would find, named by OpenSees tags rather than mesh indices.
OpenSeesMesh read_opensees_mesh(const std::filesystem::path& path,
                                const std::map<std::string, std::string>& material_of_tag,
                                const std::vector<std::string>& ignore_elements,
                                const MaterialTable& materials);

/// One row of a recorder file.
struct RecorderRow {
  double time = 0.0;
  std::vector<double> values;  ///< the columns after the time
  std::size_t line = 0;        ///< 1-based line of the file
};

/// The time of a row matches `time` within this fraction of |time| (half a unit of the
/// sixth significant digit, OpenSees's default precision), or within 1e-9 s at t = 0.
inline constexpr double recorder_time_tolerance = 5e-6;

/// Which row to take when the time repeats: OpenSees's clock goes back to 0 at
/// `loadConst -time 0.0`, so the end of a gravity stage and a later dynamic step may have
/// the same time.
enum class RepeatedTime { first, last };

/// `columns` value that accepts any number of values (the caller checks them).
inline constexpr std::size_t any_columns = static_cast<std::size_t>(-1);

/// The row of `path` at `time` (within the tolerance; the first or the last such row when
/// the time repeats). Error, naming the file and line,
/// when no row is at that time (with the first and last times there are), when a row has
/// a number that does not parse or is not finite, or when the selected row does not have
/// `columns` values after the time (`layout` says what they should be, e.g. "2 values
/// for each of 45 nodes").
RecorderRow read_recorder_row(const std::filesystem::path& path, double time, std::size_t columns,
                              std::string_view layout, RepeatedTime repeated = RepeatedTime::last);

}  // namespace slide
