// VTK XML output for ParaView: an FE mesh with node, element and Gauss-point fields,
// point clouds (material points, Gauss points) with all their fields, and a .pvd
// collection per series so ParaView animates a run. Files are written atomically.
//
// What ParaView is told (common/io/vtk-output.md has the field list, units and signs):
//  - every array has named components (x y z; xx yy zz xy; XX YY ZZ XY YZ XZ; ...);
//  - a stress-like field (stress, strain) is written twice: as `<name>` in the
//    checkpoints' order [xx, yy, zz, xy], and as `<name>_tensor`, the same tensor with 6
//    components in ParaView's symmetric-tensor order, for its tensor filters;
//  - ids, material ids, element numbers are integer arrays, flags are unsigned bytes;
//  - each file carries its time (field data `TimeValue`, which VTK's readers and
//    ParaView take as the time of a lone .vtu) and the conventions (field data
//    `conventions`: units, signs, component order).
// Arrays are stored raw in the appended section, uncompressed: a frame costs about what
// its bytes cost to write (compressing doubles saved little and cost most of a run).
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <variant>
#include <vector>

#include "common/base/types.hpp"
#include "common/geometry/element.hpp"

namespace slide {

/// How a field's values are laid out, which gives its VTK components and their names.
enum class VtkLayout {
  scalar,       ///< one value
  vector,       ///< (x, y), written as (x, y, 0) so that ParaView treats it as a vector
  stress_like,  ///< [xx, yy, zz, xy], also written as a 6-component `<name>_tensor`
  matrix,       ///< a 2×2 matrix row by row: [xx, xy, yx, yy]
};

/// One named array, one tuple per point or cell. Floating-point values are written as
/// Float64; the integer spans as Int32, Int64 and UInt8 (flags 0/1).
struct VtkField {
  std::string name;
  VtkLayout layout = VtkLayout::scalar;
  std::variant<std::span<const double>, std::span<const std::int32_t>,
               std::span<const std::int64_t>, std::span<const std::uint8_t>>
      values;
};

/// Helpers to view our arrays as fields without copying.
VtkField vtk_field(std::string name, std::span<const double> values);
VtkField vtk_field(std::string name, std::span<const Vec2> values);
/// A stress-like Vec4 [xx, yy, zz, xy] (`layout` stress_like) or a 2×2 matrix (matrix).
VtkField vtk_field(std::string name, std::span<const Vec4> values,
                   VtkLayout layout = VtkLayout::stress_like);
VtkField vtk_field(std::string name, std::span<const std::int32_t> values);
VtkField vtk_field(std::string name, std::span<const std::int64_t> values);
VtkField vtk_field(std::string name, std::span<const std::uint8_t> values);

/// An unstructured grid of quads or triangles on `points` (current coordinates), at
/// `time` (s).
void write_vtk_mesh(const std::filesystem::path& path, double time, std::span<const Vec2> points,
                    ElementShape shape, std::span<const Index> connectivity,
                    const std::vector<VtkField>& point_fields,
                    const std::vector<VtkField>& cell_fields);

/// A cloud of vertices (material points or Gauss points) with per-point fields, at
/// `time` (s).
void write_vtk_points(const std::filesystem::path& path, double time, std::span<const Vec2> points,
                      const std::vector<VtkField>& point_fields);

/// A parallel collection of point clouds (.pvtu): the pieces (file names relative to
/// the .pvtu's folder) written by write_vtk_points with these fields, one per rank, which
/// ParaView opens as one cloud.
void write_vtk_points_collection(const std::filesystem::path& path,
                                 std::span<const std::string> pieces,
                                 const std::vector<VtkField>& point_fields);

/// The text of every file's `conventions` field data.
extern const char* const vtk_conventions;

/// A ParaView collection (.pvd): (time, file) pairs, rewritten after every addition so
/// that a run stopped at any point leaves a valid collection.
class PvdCollection {
 public:
  explicit PvdCollection(std::filesystem::path path) : path_(std::move(path)) {}
  /// Records `file` (relative paths are written relative to the .pvd's folder).
  void add(double time, const std::filesystem::path& file);
  /// On restart: reloads the entries of an existing collection file written by an
  /// earlier run, keeping those with time ≤ `time`. No file: starts empty.
  void resume(double time);
  const std::filesystem::path& path() const { return path_; }

 private:
  void write() const;
  std::filesystem::path path_;
  std::vector<std::pair<double, std::string>> entries_;
};

}  // namespace slide
