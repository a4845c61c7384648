#include "common/io/hdf5_file.hpp"

#include <algorithm>
#include <array>
#include <limits>
#include <type_traits>
#include <utility>

#include <hdf5.h>

#include "common/base/error.hpp"
#include "common/base/names.hpp"
#include "common/base/program.hpp"

namespace slide::hdf5 {

// The header stores handles as std::int64_t and closers as int(*)(std::int64_t).
static_assert(std::is_same_v<hid_t, std::int64_t>, "HDF5 >= 1.10 (64-bit hid_t) expected");
static_assert(std::is_same_v<herr_t, int>);
static_assert(std::is_same_v<hsize_t, std::uint64_t> || sizeof(hsize_t) == sizeof(std::uint64_t));

namespace {

// Switches off HDF5's printing of its error stack to stderr: every failure is reported
// once, by us, as one line. Process-wide and idempotent, so calling it on every file
// open is harmless.
void silence_hdf5_errors() {
  // No library shutdown at exit: after a write that failed (a full disk) HDF5 keeps the
  // half-closed file in its tables, and its exit handler then crashed closing it again
  // (SIGSEGV in H5F__close_cb after the one-line error). Every file of ours is closed
  // (and, when written, flushed) by File before the program ends, so the shutdown has
  // nothing left to do. Only effective before the library's first call, hence here.
  static const bool no_shutdown = [] {
    H5dont_atexit();
    return true;
  }();
  (void)no_shutdown;
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
}

// What went wrong, from HDF5's error stack, on one line; the stack is cleared afterwards.
// A failed system call is reported with its errno text (HDF5's file driver puts it in
// its description as "error message = '…'"): on a full disk that is "No space left on
// device", where the innermost description can be an unrelated consequence ("slist
// already enabled?"). Otherwise the innermost description, the most specific one (e.g.
// "file signature not found").
std::string hdf5_detail() {
  struct Found {
    std::string innermost;
    std::string system;
  } found;
  auto take = [](unsigned n, const H5E_error2_t* error, void* data) -> herr_t {
    auto& f = *static_cast<Found*>(data);
    if (error->desc == nullptr) return 0;
    const std::string_view desc(error->desc);
    if (n == 0) f.innermost = desc;
    const std::string_view marker = "error message = '";
    const std::size_t start = desc.find(marker);
    if (f.system.empty() && start != std::string_view::npos) {
      const std::string_view rest = desc.substr(start + marker.size());
      f.system = rest.substr(0, rest.find('\''));
    }
    return 0;
  };
  H5Ewalk2(H5E_DEFAULT, H5E_WALK_UPWARD, take, &found);
  H5Eclear2(H5E_DEFAULT);
  std::string detail = found.system.empty() ? found.innermost : found.system;
  std::replace(detail.begin(), detail.end(), '\n', ' ');
  return detail.empty() ? std::string("HDF5 error") : detail;
}

std::string c_string(std::string_view text) {
  return std::string(text);
}

TypeClass type_class_of(hid_t type) {
  switch (H5Tget_class(type)) {
    case H5T_INTEGER:
      return TypeClass::integer;
    case H5T_FLOAT:
      return TypeClass::floating_point;
    case H5T_STRING:
      return TypeClass::string;
    default:
      return TypeClass::other;
  }
}

Handle checked(hid_t id, Handle::Closer closer, std::string_view where, std::string_view what) {
  if (id < 0) throw Error("{}: {} ({})", where, what, hdf5_detail());
  return Handle(id, closer);
}

void check(herr_t status, std::string_view where, std::string_view what) {
  if (status < 0) throw Error("{}: {} ({})", where, what, hdf5_detail());
}

/// check() of a call on a file every rank writes together (`ranks`; nullptr: one
/// process's file): a failure on any rank throws on every rank, the lowest failing rank's
/// message, so that all leave the file at the same call. A rank that threw alone would
/// close the file, itself collective, while its peers went on to the next write, and all
/// would wait for ever (a full disk under 2 ranks did). Where HDF5 itself left a peer
/// waiting inside a failed call, the failing rank ends the job after a grace period
/// (Ranks::first_problem_within).
void check_on_ranks(herr_t status, std::string_view where, std::string_view what,
                    const Ranks* ranks) {
  if (ranks == nullptr || !ranks->distributed()) return check(status, where, what);
  std::optional<std::string> problem;
  if (status < 0) problem = fmt::format("{}: {} ({})", where, what, hdf5_detail());
  if (const auto first = ranks->first_problem_within(problem)) throw Error("{}", *first);
}

/// checked() of a call on a file every rank writes together (check_on_ranks).
Handle checked_on_ranks(hid_t id, Handle::Closer closer, std::string_view where,
                        std::string_view what, const Ranks* ranks) {
  Handle handle(id, id < 0 ? nullptr : closer);
  check_on_ranks(id < 0 ? -1 : 0, where, what, ranks);
  return handle;
}

Handle scalar_space() {
  return Handle(H5Screate(H5S_SCALAR), &H5Sclose);
}

// The memory type for reading a variable-length UTF-8 string (files written by h5py).
Handle variable_utf8_string_type() {
  Handle type(H5Tcopy(H5T_C_S1), &H5Tclose);
  H5Tset_size(type.id(), H5T_VARIABLE);
  H5Tset_cset(type.id(), H5T_CSET_UTF8);
  return type;
}

// The type we write strings with: fixed-length UTF-8 of the string's byte count (at
// least 1), null-padded. A fixed-length string lives in the attribute itself; a
// variable-length one lives in the file's global heap, and a damaged heap entry crashed
// libhdf5 inside H5HG_read before it could report anything.
Handle fixed_utf8_string_type(std::size_t bytes) {
  Handle type(H5Tcopy(H5T_C_S1), &H5Tclose);
  H5Tset_size(type.id(), std::max<std::size_t>(bytes, 1));
  H5Tset_strpad(type.id(), H5T_STR_NULLPAD);
  H5Tset_cset(type.id(), H5T_CSET_UTF8);
  return type;
}

hssize_t point_count(hid_t space) {
  return H5Sget_simple_extent_npoints(space);
}

}  // namespace

std::string format_shape(const Shape& shape) {
  if (shape.empty()) return "scalar";
  std::string text;
  for (std::size_t i = 0; i < shape.size(); ++i) {
    if (i > 0) text += "×";
    text += std::to_string(shape[i]);
  }
  return text;
}

std::string_view to_string(TypeClass type_class) {
  static constexpr std::array<Named<TypeClass>, 4> names{{
      {"integer", TypeClass::integer},
      {"floating point", TypeClass::floating_point},
      {"string", TypeClass::string},
      {"other", TypeClass::other},
  }};
  return name_of(names, type_class);
}

// ---------------------------------------------------------------------------------------
// Handle

Handle::Handle(Handle&& other) noexcept
    : id_(std::exchange(other.id_, -1)), closer_(std::exchange(other.closer_, nullptr)) {}

Handle& Handle::operator=(Handle&& other) noexcept {
  if (this != &other) {
    reset();
    id_ = std::exchange(other.id_, -1);
    closer_ = std::exchange(other.closer_, nullptr);
  }
  return *this;
}

bool Handle::reset() {
  bool ok = true;
  if (id_ >= 0 && closer_ != nullptr) ok = closer_(id_) >= 0;
  // A file whose close failed stays half-closed in HDF5 1.10, and the library's own
  // termination at exit then crashes on it.
  if (!ok && closer_ == &H5Fclose) mark_library_damaged();
  id_ = -1;
  closer_ = nullptr;
  return ok;
}

// ---------------------------------------------------------------------------------------
// Object: attributes

std::string Object::where() const {
  return path_ == "/" ? file_label_ : fmt::format("{}: {}", file_label_, path_);
}

std::string Object::child_path(std::string_view name) const {
  return path_ == "/" ? fmt::format("/{}", name) : fmt::format("{}/{}", path_, name);
}

bool Object::has_attribute(std::string_view name) const {
  const htri_t exists = H5Aexists(handle_.id(), c_string(name).c_str());
  check(exists, where(), fmt::format("attribute {}: cannot query", name));
  return exists > 0;
}

std::vector<std::string> Object::attribute_names() const {
  std::vector<std::string> names;
  auto collect = [](hid_t, const char* name, const H5A_info_t*, void* data) -> herr_t {
    static_cast<std::vector<std::string>*>(data)->emplace_back(name);
    return 0;
  };
  check(H5Aiterate2(handle_.id(), H5_INDEX_NAME, H5_ITER_INC, nullptr, collect, &names), where(),
        "cannot list attributes");
  std::sort(names.begin(), names.end());
  return names;
}

Handle Object::open_attribute(std::string_view name) const {
  if (!has_attribute(name)) throw Error("{}: attribute {} missing", where(), name);
  return checked(H5Aopen(handle_.id(), c_string(name).c_str(), H5P_DEFAULT), &H5Aclose, where(),
                 fmt::format("attribute {}: cannot open", name));
}

TypeClass Object::attribute_type_class(std::string_view name) const {
  const Handle attribute = open_attribute(name);
  const Handle type(H5Aget_type(attribute.id()), &H5Tclose);
  return type_class_of(type.id());
}

namespace {

// Creates attribute `name` on `location`, replacing an existing one.
Handle create_attribute(hid_t location, std::string_view name, hid_t type, hid_t space,
                        std::string_view where, const Ranks* ranks) {
  const std::string key(name);
  if (H5Aexists(location, key.c_str()) > 0) {
    check_on_ranks(H5Adelete(location, key.c_str()), where,
                   fmt::format("attribute {}: cannot replace", name), ranks);
  }
  return checked_on_ranks(H5Acreate2(location, key.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT),
                          &H5Aclose, where, fmt::format("attribute {}: cannot create", name),
                          ranks);
}

}  // namespace

void Object::write_string_attribute(std::string_view name, std::string_view value) {
  const Handle type = fixed_utf8_string_type(value.size());
  const Handle space = scalar_space();
  const Handle attribute =
      create_attribute(handle_.id(), name, type.id(), space.id(), where(), ranks_);
  std::string buffer(value);
  buffer.resize(std::max<std::size_t>(value.size(), 1), '\0');
  check_on_ranks(H5Awrite(attribute.id(), type.id(), buffer.data()), where(),
                 fmt::format("attribute {}: cannot write", name), ranks_);
}

void Object::write_int_attribute(std::string_view name, std::int64_t value) {
  const Handle space = scalar_space();
  const Handle attribute =
      create_attribute(handle_.id(), name, H5T_STD_I64LE, space.id(), where(), ranks_);
  check_on_ranks(H5Awrite(attribute.id(), H5T_NATIVE_INT64, &value), where(),
                 fmt::format("attribute {}: cannot write", name), ranks_);
}

void Object::write_double_attribute(std::string_view name, double value) {
  const Handle space = scalar_space();
  const Handle attribute =
      create_attribute(handle_.id(), name, H5T_IEEE_F64LE, space.id(), where(), ranks_);
  check_on_ranks(H5Awrite(attribute.id(), H5T_NATIVE_DOUBLE, &value), where(),
                 fmt::format("attribute {}: cannot write", name), ranks_);
}

void Object::write_double_array_attribute(std::string_view name, std::span<const double> values) {
  const hsize_t extent = values.size();
  const Handle space(H5Screate_simple(1, &extent, nullptr), &H5Sclose);
  const Handle attribute =
      create_attribute(handle_.id(), name, H5T_IEEE_F64LE, space.id(), where(), ranks_);
  if (values.empty()) return;
  check_on_ranks(H5Awrite(attribute.id(), H5T_NATIVE_DOUBLE, values.data()), where(),
                 fmt::format("attribute {}: cannot write", name), ranks_);
}

namespace {

// Checks an attribute's type class (`accepted` lists the acceptable ones) and, when
// `single` is set, that it holds exactly one value. Returns the attribute's file type.
Handle checked_attribute_type(hid_t attribute, std::string_view where, std::string_view name,
                              std::initializer_list<TypeClass> accepted, bool single,
                              std::string_view expected) {
  Handle type(H5Aget_type(attribute), &H5Tclose);
  const TypeClass actual = type_class_of(type.id());
  if (std::find(accepted.begin(), accepted.end(), actual) == accepted.end()) {
    throw Error("{}: attribute {}: type class {}, expected {}", where, name, to_string(actual),
                expected);
  }
  if (single) {
    const Handle space(H5Aget_space(attribute), &H5Sclose);
    const hssize_t count = point_count(space.id());
    if (count != 1) {
      throw Error("{}: attribute {}: {} values, expected a single value", where, name, count);
    }
  }
  return type;
}

}  // namespace

std::string Object::read_string_attribute(std::string_view name) const {
  const Handle attribute = open_attribute(name);
  const Handle file_type =
      checked_attribute_type(attribute.id(), where(), name, {TypeClass::string}, true, "string");
  const std::string what = fmt::format("attribute {}: cannot read", name);
  if (H5Tis_variable_str(file_type.id()) > 0) {
    const Handle memory_type = variable_utf8_string_type();
    H5Tset_cset(memory_type.id(), H5Tget_cset(file_type.id()));
    char* pointer = nullptr;
    check(H5Aread(attribute.id(), memory_type.id(), &pointer), where(), what);
    std::string value = pointer != nullptr ? std::string(pointer) : std::string();
    H5free_memory(pointer);
    return value;
  }
  // Fixed-length (e.g. numpy bytes): read the padded buffer and cut at the padding.
  const std::size_t size = H5Tget_size(file_type.id());
  const Handle memory_type(H5Tcopy(file_type.id()), &H5Tclose);
  H5Tset_strpad(memory_type.id(), H5T_STR_NULLTERM);
  H5Tset_size(memory_type.id(), size + 1);
  std::string buffer(size + 1, '\0');
  check(H5Aread(attribute.id(), memory_type.id(), buffer.data()), where(), what);
  buffer.resize(buffer.find('\0'));
  if (H5Tget_strpad(file_type.id()) == H5T_STR_SPACEPAD) {
    buffer.erase(buffer.find_last_not_of(' ') + 1);
  }
  return buffer;
}

std::int64_t Object::read_int_attribute(std::string_view name) const {
  const Handle attribute = open_attribute(name);
  checked_attribute_type(attribute.id(), where(), name, {TypeClass::integer}, true, "integer");
  std::int64_t value = 0;
  check(H5Aread(attribute.id(), H5T_NATIVE_INT64, &value), where(),
        fmt::format("attribute {}: cannot read", name));
  return value;
}

double Object::read_double_attribute(std::string_view name) const {
  const Handle attribute = open_attribute(name);
  checked_attribute_type(attribute.id(), where(), name,
                         {TypeClass::floating_point, TypeClass::integer}, true, "a number");
  double value = 0.0;
  check(H5Aread(attribute.id(), H5T_NATIVE_DOUBLE, &value), where(),
        fmt::format("attribute {}: cannot read", name));
  return value;
}

std::vector<double> Object::read_double_array_attribute(std::string_view name) const {
  const Handle attribute = open_attribute(name);
  checked_attribute_type(attribute.id(), where(), name,
                         {TypeClass::floating_point, TypeClass::integer}, false, "numbers");
  const Handle space(H5Aget_space(attribute.id()), &H5Sclose);
  std::vector<double> values(
      static_cast<std::size_t>(std::max<hssize_t>(point_count(space.id()), 0)));
  if (values.empty()) return values;
  check(H5Aread(attribute.id(), H5T_NATIVE_DOUBLE, values.data()), where(),
        fmt::format("attribute {}: cannot read", name));
  return values;
}

// ---------------------------------------------------------------------------------------
// Dataset

Shape Dataset::shape() const {
  const Handle space = checked(H5Dget_space(handle_.id()), &H5Sclose, where(), "cannot read shape");
  const int rank = H5Sget_simple_extent_ndims(space.id());
  check(rank, where(), "cannot read shape");
  std::vector<hsize_t> extents(static_cast<std::size_t>(rank));
  if (rank > 0) {
    check(H5Sget_simple_extent_dims(space.id(), extents.data(), nullptr), where(),
          "cannot read shape");
  }
  return Shape(extents.begin(), extents.end());
}

TypeClass Dataset::type_class() const {
  const Handle type = checked(H5Dget_type(handle_.id()), &H5Tclose, where(), "cannot read type");
  return type_class_of(type.id());
}

namespace {

std::size_t element_count(const Shape& shape) {
  std::size_t count = 1;
  for (const auto extent : shape) count *= extent;
  return count;
}

template <typename T>
std::vector<T> read_all(hid_t dataset, hid_t memory_type, const Shape& shape,
                        std::string_view where) {
  std::vector<T> values(element_count(shape));
  if (values.empty()) return values;
  check(H5Dread(dataset, memory_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()), where,
        "cannot read");
  return values;
}

/// Rows [first, first + count) of the dataset, every column.
template <typename T>
std::vector<T> read_rows(hid_t dataset, hid_t memory_type, const Shape& shape, const RowRange& rows,
                         std::string_view where) {
  // Rows of the 1-D and 2-D datasets the checkpoints hold.
  if (shape.empty() || shape.size() > 2 || rows.first > shape[0] ||
      rows.count > shape[0] - rows.first) {
    throw Error("{}: rows {}–{} asked of a dataset of shape {}", where, rows.first,
                rows.first + rows.count, format_shape(shape));
  }
  const hsize_t columns = shape.size() == 2 ? shape[1] : 1;
  const std::array<hsize_t, 2> start{rows.first, 0}, block{rows.count, columns};
  std::vector<T> values(rows.count * columns);
  if (values.empty()) return values;
  const Handle file_space = checked(H5Dget_space(dataset), &H5Sclose, where, "cannot read shape");
  check(H5Sselect_hyperslab(file_space.id(), H5S_SELECT_SET, start.data(), nullptr, block.data(),
                            nullptr),
        where, "cannot select rows");
  const Handle memory =
      checked(H5Screate_simple(static_cast<int>(shape.size()), block.data(), nullptr), &H5Sclose,
              where, "cannot make a memory space");
  check(H5Dread(dataset, memory_type, memory.id(), file_space.id(), H5P_DEFAULT, values.data()),
        where, "cannot read");
  return values;
}

}  // namespace

std::vector<double> Dataset::read_doubles(const std::optional<RowRange>& rows) const {
  if (rows) return read_rows<double>(handle_.id(), H5T_NATIVE_DOUBLE, shape(), *rows, where());
  return read_all<double>(handle_.id(), H5T_NATIVE_DOUBLE, shape(), where());
}

std::vector<std::int64_t> Dataset::read_int64(const std::optional<RowRange>& rows) const {
  if (rows) return read_rows<std::int64_t>(handle_.id(), H5T_NATIVE_INT64, shape(), *rows, where());
  return read_all<std::int64_t>(handle_.id(), H5T_NATIVE_INT64, shape(), where());
}

std::vector<std::int32_t> Dataset::read_int32() const {
  const std::vector<std::int64_t> wide = read_int64();
  std::vector<std::int32_t> values(wide.size());
  for (std::size_t i = 0; i < wide.size(); ++i) {
    if (wide[i] < std::numeric_limits<std::int32_t>::min() ||
        wide[i] > std::numeric_limits<std::int32_t>::max()) {
      throw Error("{}: value {} at index {} does not fit a 32-bit integer", where(), wide[i], i);
    }
    values[i] = static_cast<std::int32_t>(wide[i]);
  }
  return values;
}

// ---------------------------------------------------------------------------------------
// Group

bool Group::contains(std::string_view name) const {
  // H5Lexists checks only the last component: walk the path one component at a time.
  std::size_t end = 0;
  while (end != std::string_view::npos) {
    end = name.find('/', end + 1);
    const std::string prefix(name.substr(0, end));
    if (H5Lexists(handle_.id(), prefix.c_str(), H5P_DEFAULT) <= 0) {
      H5Eclear2(H5E_DEFAULT);
      return false;
    }
  }
  return true;
}

std::vector<std::string> Group::member_names() const {
  std::vector<std::string> names;
  // Generic lambda: its conversion to the callback type fits H5L_info_t (1.10) and
  // H5L_info2_t (1.12+) alike.
  auto collect = [](hid_t, const char* name, const auto*, void* data) -> herr_t {
    static_cast<std::vector<std::string>*>(data)->emplace_back(name);
    return 0;
  };
  check(H5Literate(handle_.id(), H5_INDEX_NAME, H5_ITER_INC, nullptr, collect, &names), where(),
        "cannot list members");
  std::sort(names.begin(), names.end());
  return names;
}

namespace {

// Creation properties without modification times in the object headers: the same data
// then gives the same file byte for byte, which the pipelines and tests rely on.
Handle untimed_creation_properties(hid_t property_class) {
  Handle properties(H5Pcreate(property_class), &H5Pclose);
  H5Pset_obj_track_times(properties.id(), false);
  return properties;
}

// Row-chunked storage with HDF5's Fletcher32 checksum on every chunk: a damaged byte in
// the data then fails the read as "data error detected by Fletcher32 checksum" instead
// of passing as a wrong number. Chunks hold whole rows, about 1 MiB each. Scalars and
// empty datasets stay contiguous (nothing to chunk; a scalar is checked by its range).
void add_checksum(hid_t properties, const std::vector<hsize_t>& extents, std::size_t value_bytes,
                  std::string_view where) {
  if (extents.empty() || std::find(extents.begin(), extents.end(), 0) != extents.end()) return;
  hsize_t row_bytes = value_bytes;
  for (std::size_t i = 1; i < extents.size(); ++i) row_bytes *= extents[i];
  constexpr hsize_t chunk_bytes = 1 << 20;
  std::vector<hsize_t> chunk = extents;
  chunk[0] = std::clamp<hsize_t>(chunk_bytes / std::max<hsize_t>(row_bytes, 1), 1, extents[0]);
  check(H5Pset_chunk(properties, static_cast<int>(chunk.size()), chunk.data()), where,
        "cannot set chunks");
  check(H5Pset_fletcher32(properties), where, "cannot set the Fletcher32 checksum");
}

}  // namespace

Group Group::create_group(std::string_view name) {
  const std::string path = child_path(name);
  const Handle properties = untimed_creation_properties(H5P_GROUP_CREATE);
  Handle group = checked_on_ranks(
      H5Gcreate2(handle_.id(), c_string(name).c_str(), H5P_DEFAULT, properties.id(), H5P_DEFAULT),
      &H5Gclose, fmt::format("{}: {}", file_label_, path), "cannot create group", ranks_);
  return Group(std::move(group), file_label_, path, ranks_);
}

namespace {

// Opens the object `name` below `location` and checks that it is of `kind`.
Handle open_object(hid_t location, std::string_view name, H5I_type_t kind, bool exists,
                   std::string_view where, std::string_view noun) {
  if (!exists) throw Error("{}: {} missing", where, noun);
  Handle object = checked(H5Oopen(location, std::string(name).c_str(), H5P_DEFAULT), &H5Oclose,
                          where, fmt::format("cannot open {}", noun));
  if (H5Iget_type(object.id()) != kind) throw Error("{}: not a {}", where, noun);
  return object;
}

}  // namespace

Group Group::open_group(std::string_view name) const {
  const std::string path = child_path(name);
  Handle group = open_object(handle_.id(), name, H5I_GROUP, contains(name),
                             fmt::format("{}: {}", file_label_, path), "group");
  return Group(std::move(group), file_label_, path, ranks_);
}

Dataset Group::open_dataset(std::string_view name) const {
  const std::string path = child_path(name);
  Handle dataset = open_object(handle_.id(), name, H5I_DATASET, contains(name),
                               fmt::format("{}: {}", file_label_, path), "dataset");
  return Dataset(std::move(dataset), file_label_, path, ranks_);
}

namespace {

/// The data of a dataset in a collective file, written by every rank at once: its
/// rows (`share`) or, without, the root's copy of values every rank holds.
void write_collectively(hid_t dataset, hid_t file_space, const void* values, std::size_t count,
                        const Shape& shape, hid_t memory_type, const RowShare* share,
                        const std::string& at, const Ranks& ranks) {
#if SLIDE_MPI
  const Handle transfer(H5Pcreate(H5P_DATASET_XFER), &H5Pclose);
  check(H5Pset_dxpl_mpio(transfer.id(), H5FD_MPIO_COLLECTIVE), at, "cannot select collective I/O");
  const std::vector<hsize_t> local(shape.begin(), shape.end());
  Handle memory =
      local.empty()
          ? scalar_space()
          : Handle(H5Screate_simple(static_cast<int>(local.size()), local.data(), nullptr),
                   &H5Sclose);
  if (share != nullptr) {
    std::vector<hsize_t> start(local.size(), 0), block(local.begin(), local.end());
    bool first = true;
    std::uint64_t rows = 0;
    for (const auto& [row, row_count] : share->ranges) {
      if (row_count == 0) continue;
      start[0] = row;
      block[0] = row_count;
      check(H5Sselect_hyperslab(file_space, first ? H5S_SELECT_SET : H5S_SELECT_OR, start.data(),
                                nullptr, block.data(), nullptr),
            at, "cannot select this rank's rows");
      first = false;
      rows += row_count;
    }
    if (rows != local[0])
      throw Error("{}: this rank holds {} rows but its share names {}", at, local[0], rows);
    if (first) {
      check(H5Sselect_none(file_space), at, "cannot select no rows");
      check(H5Sselect_none(memory.id()), at, "cannot select no rows");
    }
  } else if (!ranks.root()) {
    check(H5Sselect_none(file_space), at, "cannot select no rows");
    check(H5Sselect_none(memory.id()), at, "cannot select no rows");
  }
  static const double nothing = 0.0;  // HDF5 wants a buffer even for no values
  check_on_ranks(H5Dwrite(dataset, memory_type, memory.id(), file_space, transfer.id(),
                          count > 0 ? values : &nothing),
                 at, "cannot write dataset", &ranks);
#else
  (void)dataset, (void)file_space, (void)values, (void)count, (void)shape, (void)memory_type,
      (void)share, (void)ranks;
  throw Error("{}: a collective write needs the MPI build", at);
#endif
}

}  // namespace

Dataset Group::write_dataset(std::string_view name, std::span<const double> values,
                             const Shape& shape, const RowShare* share) {
  return write_dataset(name, values.data(), values.size(), shape, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE,
                       share);
}

Dataset Group::write_dataset(std::string_view name, std::span<const std::int64_t> values,
                             const Shape& shape, const RowShare* share) {
  return write_dataset(name, values.data(), values.size(), shape, H5T_STD_I64LE, H5T_NATIVE_INT64,
                       share);
}

Dataset Group::write_dataset(std::string_view name, std::span<const std::int32_t> values,
                             const Shape& shape, const RowShare* share) {
  return write_dataset(name, values.data(), values.size(), shape, H5T_STD_I32LE, H5T_NATIVE_INT32,
                       share);
}

Dataset Group::write_dataset(std::string_view name, const void* values, std::size_t count,
                             const Shape& shape, std::int64_t file_type, std::int64_t memory_type,
                             const RowShare* share) {
  const std::string path = child_path(name);
  const std::string at = fmt::format("{}: {}", file_label_, path);
  if (count != element_count(shape)) {
    throw Error("{}: {} values do not fill shape {}", at, count, format_shape(shape));
  }
  if (share != nullptr && (ranks_ == nullptr || shape.empty())) {
    throw Error("{}: shared rows need a collective file and a dataset of rows", at);
  }
  // The file's extents: this process's rows, or all processes' rows.
  std::vector<hsize_t> extents;
  extents.reserve(shape.size());
  for (std::size_t i = 0; i < shape.size(); ++i)
    extents.push_back(i == 0 && share != nullptr ? share->total : shape[i]);
  const Handle space =
      extents.empty()
          ? scalar_space()
          : Handle(H5Screate_simple(static_cast<int>(extents.size()), extents.data(), nullptr),
                   &H5Sclose);
  const Handle properties = untimed_creation_properties(H5P_DATASET_CREATE);
  add_checksum(properties.id(), extents, H5Tget_size(static_cast<hid_t>(file_type)), at);
  Handle dataset =
      checked_on_ranks(H5Dcreate2(handle_.id(), c_string(name).c_str(), file_type, space.id(),
                                  H5P_DEFAULT, properties.id(), H5P_DEFAULT),
                       &H5Dclose, at, "cannot create dataset", ranks_);
  if (ranks_ == nullptr) {
    if (count > 0) {
      check(H5Dwrite(dataset.id(), memory_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, values), at,
            "cannot write dataset");
    }
    return Dataset(std::move(dataset), file_label_, path, ranks_);
  }
  const bool empty = std::find(extents.begin(), extents.end(), hsize_t{0}) != extents.end();
  if (!empty)
    write_collectively(dataset.id(), space.id(), values, count, shape, memory_type, share, at,
                       *ranks_);
  return Dataset(std::move(dataset), file_label_, path, ranks_);
}

// ---------------------------------------------------------------------------------------
// File

File File::create(const std::filesystem::path& path, std::string label) {
  silence_hdf5_errors();
  if (label.empty()) label = path.string();
  // The 1.8 file format, no older and no newer: its object headers and the other
  // metadata carry checksums, so a damaged header is reported as damaged too, and any
  // HDF5 from 1.8 on reads it, whichever HDF5 wrote it.
  const Handle access(H5Pcreate(H5P_FILE_ACCESS), &H5Pclose);
  check(H5Pset_libver_bounds(access.id(), H5F_LIBVER_V18, H5F_LIBVER_V18), label,
        "cannot select the file format");
  // The root group's header carries time stamps in this format unless told not to, like
  // every other object (see untimed_creation_properties).
  const Handle creation = untimed_creation_properties(H5P_FILE_CREATE);
  Handle file = checked(H5Fcreate(path.c_str(), H5F_ACC_TRUNC, creation.id(), access.id()),
                        &H5Fclose, label, "cannot create HDF5 file");
  return File(std::move(file), std::move(label), "/");
}

File File::create_collective(const std::filesystem::path& path, std::string label,
                             const Ranks& ranks) {
  if (!ranks.distributed()) return create(path, std::move(label));
#if SLIDE_MPI
  silence_hdf5_errors();
  if (label.empty()) label = path.string();
  const Handle access(H5Pcreate(H5P_FILE_ACCESS), &H5Pclose);
  check(H5Pset_fapl_mpio(access.id(), ranks.communicator(), MPI_INFO_NULL), label,
        "cannot select parallel HDF5");
  check(H5Pset_libver_bounds(access.id(), H5F_LIBVER_V18, H5F_LIBVER_V18), label,
        "cannot select the file format");
  const Handle creation = untimed_creation_properties(H5P_FILE_CREATE);
  Handle file = checked(H5Fcreate(path.c_str(), H5F_ACC_TRUNC, creation.id(), access.id()),
                        &H5Fclose, label, "cannot create HDF5 file");
  return File(std::move(file), std::move(label), "/", &ranks);
#else
  throw Error("{}: a collective file needs the MPI build", label.empty() ? path.string() : label);
#endif
}

File File::open(const std::filesystem::path& path) {
  silence_hdf5_errors();
  const std::string label = path.string();
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) throw Error("{}: cannot open: no such file", label);
  if (std::filesystem::is_directory(path, ec)) throw Error("{}: is a folder, not a file", label);
  const htri_t is_hdf5 = H5Fis_hdf5(path.c_str());
  if (is_hdf5 == 0) throw Error("{}: not an HDF5 file", label);
  if (is_hdf5 < 0) throw Error("{}: cannot read ({})", label, hdf5_detail());
  Handle file = checked(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), &H5Fclose, label,
                        "cannot open as HDF5");
  return File(std::move(file), label, "/");
}

void File::close() {
  if (!handle_.valid()) return;
  const herr_t flushed = H5Fflush(handle_.id(), H5F_SCOPE_GLOBAL);
  const bool closed = handle_.reset();
  check_on_ranks(flushed < 0 || !closed ? -1 : 0, file_label_, "cannot write the file", ranks_);
}

}  // namespace slide::hdf5
