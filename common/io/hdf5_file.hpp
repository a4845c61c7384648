// A small RAII layer over the HDF5 C API, internal to common/ (checkpoint.cpp is its
// user; other libraries go through checkpoint.hpp).
//
// Every HDF5 handle is owned by exactly one object and closed in its destructor.
// HDF5's automatic error-stack printing is switched off: a failing call becomes one
// `Error` whose single line names the file, the object path and what went wrong, e.g.
// `out/fem_t2.000.h5: /nodes/velocity: dataset missing`.
//
// The header does not include <hdf5.h>: handles are stored as std::int64_t (HDF5 1.10's
// hid_t, checked in the .cpp), so HDF5's macros stay inside hdf5_file.cpp.
//
// Data layout: row-major, one value per element; an n×k dataset is passed as a flat span
// of n·k values with shape {n, k}. Files store float64, int64 and int32 little-endian;
// strings are scalar variable-length UTF-8 (what h5py writes and reads as `str`).
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "common/base/ranks.hpp"

namespace slide::hdf5 {

/// Extent of each dimension of a dataset; rank = size().
using Shape = std::vector<std::uint64_t>;
/// "2000×4", "2000", or "scalar" for rank 0.
std::string format_shape(const Shape& shape);

/// The HDF5 type class of stored data, as far as a reader cares.
enum class TypeClass { integer, floating_point, string, other };
std::string_view to_string(TypeClass type_class);

/// The rows of a dataset one process writes in a file several write together (a
/// collective file, File::create_collective): the dataset has `total` rows, and this
/// process's values go, in order, to the row ranges (first row, row count), which
/// ascend.
struct RowShare {
  std::uint64_t total = 0;
  std::vector<std::pair<std::uint64_t, std::uint64_t>> ranges;
};

/// Rows [first, first + count) of a dataset: the part one process reads of a file that
/// several read, each its own rows.
struct RowRange {
  std::uint64_t first = 0;
  std::uint64_t count = 0;
};

/// Owns one hid_t and closes it with the matching H5*close on destruction. Move-only.
class Handle {
 public:
  using Closer = int (*)(std::int64_t);
  Handle() = default;
  Handle(std::int64_t id, Closer closer) : id_(id), closer_(closer) {}
  Handle(Handle&& other) noexcept;
  Handle& operator=(Handle&& other) noexcept;
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  ~Handle() { reset(); }

  std::int64_t id() const { return id_; }
  bool valid() const { return id_ >= 0; }
  /// Closes now; returns false when HDF5 reported a failure (e.g. a failed flush).
  bool reset();

 private:
  std::int64_t id_ = -1;
  Closer closer_ = nullptr;
};

/// Anything that carries attributes: the file's root group, a group or a dataset.
class Object {
 public:
  /// The file as named in messages (the target of a write, not its temporary name).
  const std::string& file_label() const { return file_label_; }
  /// Absolute path inside the file, "/" for the root.
  const std::string& path() const { return path_; }
  /// "file" for the root, "file: /group/name" otherwise: the prefix of every message.
  std::string where() const;

  bool has_attribute(std::string_view name) const;
  std::vector<std::string> attribute_names() const;  ///< sorted by name
  TypeClass attribute_type_class(std::string_view name) const;

  /// Scalar attributes, replacing any existing attribute of that name.
  void write_string_attribute(std::string_view name, std::string_view value);
  void write_int_attribute(std::string_view name, std::int64_t value);
  void write_double_attribute(std::string_view name, double value);
  /// A 1-D float64 array attribute.
  void write_double_array_attribute(std::string_view name, std::span<const double> values);

  /// Each throws Error when the attribute is missing or of another type class. Integer
  /// attributes must hold one value; double attributes accept integer or float data.
  std::string read_string_attribute(std::string_view name) const;
  std::int64_t read_int_attribute(std::string_view name) const;
  double read_double_attribute(std::string_view name) const;
  std::vector<double> read_double_array_attribute(std::string_view name) const;

 protected:
  Object() = default;
  Object(Handle handle, std::string file_label, std::string path, const Ranks* ranks = nullptr)
      : handle_(std::move(handle)),
        file_label_(std::move(file_label)),
        path_(std::move(path)),
        ranks_(ranks) {}
  std::string child_path(std::string_view name) const;

  Handle handle_;
  std::string file_label_;
  std::string path_;
  const Ranks* ranks_ = nullptr;  ///< the ranks writing a collective file together

 private:
  Handle open_attribute(std::string_view name) const;
};

class Dataset : public Object {
 public:
  Shape shape() const;
  TypeClass type_class() const;

  /// The whole dataset, or the rows `rows` of it, converted to the requested type by
  /// HDF5. read_int32 throws when a stored value does not fit.
  std::vector<double> read_doubles(const std::optional<RowRange>& rows = std::nullopt) const;
  std::vector<std::int64_t> read_int64(const std::optional<RowRange>& rows = std::nullopt) const;
  std::vector<std::int32_t> read_int32() const;

 private:
  friend class Group;
  using Object::Object;
};

class Group : public Object {
 public:
  /// True when a link `name` exists; `name` may be a relative path "a/b".
  bool contains(std::string_view name) const;
  /// Names of the direct members (groups and datasets), sorted by name.
  std::vector<std::string> member_names() const;

  Group create_group(std::string_view name);
  /// Throws Error "…: group missing" or "…: not a group".
  Group open_group(std::string_view name) const;
  /// Throws Error "…: dataset missing" or "…: not a dataset".
  Dataset open_dataset(std::string_view name) const;

  /// New dataset `name` of the given shape (product of extents = values.size()). In a
  /// collective file (collective call): with a `share`, `shape` is this process's rows
  /// and the dataset has share->total of them; without, every process passes the same
  /// values and the root writes them.
  Dataset write_dataset(std::string_view name, std::span<const double> values, const Shape& shape,
                        const RowShare* share = nullptr);
  Dataset write_dataset(std::string_view name, std::span<const std::int64_t> values,
                        const Shape& shape, const RowShare* share = nullptr);
  Dataset write_dataset(std::string_view name, std::span<const std::int32_t> values,
                        const Shape& shape, const RowShare* share = nullptr);

 protected:
  using Object::Object;

 private:
  Dataset write_dataset(std::string_view name, const void* values, std::size_t count,
                        const Shape& shape, std::int64_t file_type, std::int64_t memory_type,
                        const RowShare* share);
};

class File : public Group {
 public:
  /// Creates (truncates) `path`. Messages name `label` (default: the path).
  static File create(const std::filesystem::path& path, std::string label = {});
  /// Creates `path` for every rank to write together with parallel HDF5 (collective;
  /// MPI build: create on one rank otherwise): every call on the file, its groups and
  /// datasets is then collective, attributes included (same values on every rank).
  static File create_collective(const std::filesystem::path& path, std::string label,
                                const Ranks& ranks);
  /// Opens `path` read-only; throws Error when it is missing, not HDF5 or unreadable.
  static File open(const std::filesystem::path& path);

  /// Flushes and closes the file; throws Error when HDF5 cannot (e.g. disk full). Every
  /// group and dataset taken from the file must be closed (destroyed) before.
  void close();

 private:
  using Group::Group;
};

}  // namespace slide::hdf5
