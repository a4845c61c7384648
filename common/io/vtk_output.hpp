// VTK XML output for ParaView: an FE mesh with node, element and Gauss-point fields,
// point clouds (material points, Gauss points) with all their fields, and a .pvd
// collection per series so ParaView animates a run. Files are written atomically.
#pragma once

#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "common/base/types.hpp"
#include "common/geometry/element.hpp"

namespace slide {

/// One named array: `components` values per point or cell, row by row. Two-component
/// vectors are padded to three so ParaView treats them as vectors.
struct VtkField {
  std::string name;
  int components = 1;
  std::span<const double> values;
};

/// Helpers to view our arrays as fields without copying.
VtkField vtk_field(std::string name, std::span<const double> values);
VtkField vtk_field(std::string name, std::span<const Vec2> values);
VtkField vtk_field(std::string name, std::span<const Vec4> values);

/// An unstructured grid of quads or triangles on `points` (current coordinates).
void write_vtk_mesh(const std::filesystem::path& path, std::span<const Vec2> points,
                    ElementShape shape, std::span<const Index> connectivity,
                    const std::vector<VtkField>& point_fields,
                    const std::vector<VtkField>& cell_fields);

/// A cloud of vertices (material points or Gauss points) with per-point fields.
void write_vtk_points(const std::filesystem::path& path, std::span<const Vec2> points,
                      const std::vector<VtkField>& point_fields);

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
