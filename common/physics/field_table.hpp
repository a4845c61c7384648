// Field tables: one list of fields for each structure of per-row arrays (the material
// points of common/physics/particles.hpp, the FE state of common/physics/fe_fields.hpp).
// An entry names a member, the rows it has (particles; FE nodes, elements or Gauss
// points), its checkpoint dataset and unit, and how it behaves (always present or only
// when a run uses it, its fill value, the check a checkpoint makes of it). The generic
// operations below, the MPI packing (mpm/domain.cpp) and the checkpoint reader and writer
// (common/io/checkpoint.cpp) walk the list instead of naming fields, and
// checkpoint-schema.md's tables are checked against it (tests/common/test_field_tables):
// a new field is one entry, plus its physics.
//
// A column is a std::vector<T> with T a number, a Vec2/Vec4, an index, or a
// MaterialState (whose own members are listed in material_state_fields, datasets
// state/<name>), or the SurfaceStresses of the multi-yield model (`per_point` entries a
// row, dataset state/surface_stress).
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <optional>
#include <string_view>
#include <tuple>
#include <type_traits>
#include <utility>
#include <vector>

#include "common/base/types.hpp"
#include "common/physics/material_state.hpp"

namespace slide {

/// The rows a field has.
enum class RowKind : std::uint8_t { particle, node, element, gauss_point };

/// always: one entry per row. when_used: empty unless the run uses the field (APIC's
/// affine velocity, the hourglass forces of one-point quads); an empty column stays
/// empty when the rows are resized, and a checkpoint holds it only when it is set.
enum class Presence : std::uint8_t { always, when_used };

/// What a checkpoint checks of a field beyond finite values within the dataset's
/// magnitude rule (common/io/checkpoint.cpp).
enum class Check : std::uint8_t {
  none,
  positive,        ///< every value > 0 (volume, mass)
  positive_size,   ///< both sides of a particle's domain > 0
  material,        ///< an index into /materials
  source_element,  ///< −1 (pure MPM) or an FE element
  unique_id,       ///< ≥ 0, no two rows alike
  flag,            ///< 0 or 1
};

/// What a new row holds.
enum class Fill : std::uint8_t { zero, minus_one };

template <class Owner, class Column>
struct Field {
  using owner_type = Owner;
  using column_type = Column;
  Column Owner::*member;
  std::string_view name;  ///< the dataset under the rows' group, e.g. "velocity"
  std::string_view unit;  ///< the dataset's units attribute ("1": dimensionless)
  RowKind rows = RowKind::particle;
  Presence presence = Presence::always;
  Check check = Check::none;
  Fill fill = Fill::zero;

  Column& of(Owner& owner) const { return owner.*member; }
  const Column& of(const Owner& owner) const { return owner.*member; }
};

/// How a field behaves, beyond its member, name and unit (designated initialisers:
/// `{.presence = Presence::when_used}`).
struct FieldOptions {
  RowKind rows = RowKind::particle;
  Presence presence = Presence::always;
  Check check = Check::none;
  Fill fill = Fill::zero;
};

/// A table entry.
template <class Owner, class Column>
constexpr Field<Owner, Column> field(Column Owner::*member, std::string_view name,
                                     std::string_view unit, FieldOptions options = {}) {
  return {member, name, unit, options.rows, options.presence, options.check, options.fill};
}

/// The bytes of the columns a table lists: equal to sizeof(Owner) when it lists every
/// member (a static_assert beside each table).
template <class Table>
constexpr std::size_t listed_bytes() {
  return []<class... Fields>(std::type_identity<std::tuple<Fields...>>) {
    return (sizeof(typename Fields::column_type) + ... + 0);
  }(std::type_identity<Table>{});
}

/// The members of MaterialState as checkpoints store them (datasets state/<name>).
/// with_surfaces: only where some point carries multi-yield surfaces.
enum class StatePresence : std::uint8_t { always, with_surfaces };

struct StateField {
  double MaterialState::*member;
  std::string_view name;
  std::string_view unit;
  StatePresence presence = StatePresence::always;
};

inline constexpr std::array material_state_fields{
    StateField{&MaterialState::plastic_shear_strain, "plastic_shear_strain", "1"},
    StateField{&MaterialState::plastic_volumetric_strain, "plastic_volumetric_strain", "1"},
    // The frozen peak strength of the multi-yield model (negative: not frozen yet).
    StateField{&MaterialState::peak_strength, "peak_strength", "Pa", StatePresence::with_surfaces},
};
static_assert(sizeof(MaterialState) == material_state_fields.size() * sizeof(double),
              "a member was added to MaterialState: list it in material_state_fields");

/// f(field) for every field of `table` (a tuple of Field), in order.
template <class Table, class F>
void for_each_field(const Table& table, F&& f) {
  std::apply([&](const auto&... field) { (f(field), ...); }, table);
}

// ----------------------------------------------------------------------------- columns

namespace column {

template <class T>
T fill_value(Fill fill) {
  if constexpr (std::is_arithmetic_v<T>) {
    return fill == Fill::minus_one ? T(-1) : T(0);
  } else if constexpr (std::is_same_v<T, MaterialState>) {
    return MaterialState{};
  } else {
    return T::Zero();
  }
}

template <class T>
void resize(std::vector<T>& c, std::size_t n, Fill fill, Presence presence) {
  if (presence == Presence::when_used && c.empty()) return;
  c.resize(n, fill_value<T>(fill));
}
inline void resize(SurfaceStresses& c, std::size_t n, Fill, Presence) {
  c.resize(n);
}

template <class T>
void shrink(std::vector<T>& c) {
  c.shrink_to_fit();
}
inline void shrink(SurfaceStresses& c) {
  c.values.shrink_to_fit();
}

/// Rows the column holds (SurfaceStresses: points; 0 for an unused one).
template <class T>
std::size_t rows(const std::vector<T>& c) {
  return c.size();
}
inline std::size_t rows(const SurfaceStresses& c) {
  return c.points();
}

/// Whether the run leaves the column unused (empty; surfaces without any per point).
template <class T>
bool unused(const std::vector<T>& c, Presence presence) {
  return presence == Presence::when_used && c.empty();
}
inline bool unused(const SurfaceStresses& c, Presence) {
  return c.per_point == 0;
}

template <class T>
std::size_t bytes(const std::vector<T>& c) {
  return c.capacity() * sizeof(T);
}
inline std::size_t bytes(const SurfaceStresses& c) {
  return c.values.capacity() * sizeof(Vec4);
}
/// The bytes of the values a column holds (what a file stores), not of its capacity.
template <class T>
std::size_t data_bytes(const std::vector<T>& c) {
  return c.size() * sizeof(T);
}
inline std::size_t data_bytes(const SurfaceStresses& c) {
  return c.values.size() * sizeof(Vec4);
}

/// Row `from` copied to row `to` (an unused column has none).
template <class T>
void move(std::vector<T>& c, std::size_t to, std::size_t from) {
  if (!c.empty()) c[to] = c[from];
}
inline void move(SurfaceStresses& c, std::size_t to, std::size_t from) {
  const auto source = c.of(from);
  std::copy(source.begin(), source.end(), c.of(to).begin());
}

/// One row of a column by value: the buffer of an in-place permutation.
template <class Column>
struct Entry;
template <class T>
struct Entry<std::vector<T>> {
  T value;
  void load(const std::vector<T>& c, std::size_t k) {
    if (!c.empty()) value = c[k];
  }
  void store(std::vector<T>& c, std::size_t k) const {
    if (!c.empty()) c[k] = value;
  }
};
template <>
struct Entry<SurfaceStresses> {
  std::array<Vec4, max_yield_surfaces> value;
  void load(const SurfaceStresses& c, std::size_t k) {
    const auto own = c.of(k);
    std::copy(own.begin(), own.end(), value.begin());
  }
  void store(SurfaceStresses& c, std::size_t k) const {
    const auto own = c.of(k);
    std::copy(value.begin(), value.begin() + static_cast<std::ptrdiff_t>(own.size()), own.begin());
  }
};

}  // namespace column

// ----------------------------------------------------------------------------- rows

/// Resizes every field of `table` with rows `kind` to n rows (new rows filled).
template <class Table, class Owner>
void resize_rows(const Table& table, Owner& owner, RowKind kind, std::size_t n) {
  for_each_field(table, [&](const auto& field) {
    if (field.rows == kind) column::resize(field.of(owner), n, field.fill, field.presence);
  });
}

/// Releases the spare capacity of every field (one at a time).
template <class Table, class Owner>
void shrink_rows(const Table& table, Owner& owner) {
  for_each_field(table, [&](const auto& field) { column::shrink(field.of(owner)); });
}

/// Bytes held by the fields of `table`.
template <class Table, class Owner>
std::size_t field_bytes(const Table& table, const Owner& owner) {
  std::size_t total = 0;
  for_each_field(table, [&](const auto& field) { total += column::bytes(field.of(owner)); });
  return total;
}

/// The bytes of the values the columns hold: about what a checkpoint of them stores.
template <class Table, class Owner>
std::size_t field_data_bytes(const Table& table, const Owner& owner) {
  std::size_t total = 0;
  for_each_field(table, [&](const auto& field) { total += column::data_bytes(field.of(owner)); });
  return total;
}

/// The first field with rows `kind` whose row count is not n (an unused field may be
/// empty), or nothing.
template <class Table, class Owner>
std::optional<std::string_view> field_of_wrong_size(const Table& table, const Owner& owner,
                                                    RowKind kind, std::size_t n) {
  std::optional<std::string_view> wrong;
  for_each_field(table, [&](const auto& field) {
    if (wrong || field.rows != kind) return;
    const auto& column = field.of(owner);
    if (column::rows(column) != n && !column::unused(column, field.presence)) wrong = field.name;
  });
  return wrong;
}

/// Row `from` of every field copied to row `to`.
template <class Table, class Owner>
void move_row(const Table& table, Owner& owner, std::size_t to, std::size_t from) {
  for_each_field(table, [&](const auto& field) { column::move(field.of(owner), to, from); });
}

/// One row of every field of a table, by value.
template <class Table>
struct RowBuffer;
template <class... Fields>
struct RowBuffer<std::tuple<Fields...>> {
  std::tuple<column::Entry<typename Fields::column_type>...> entries;

  template <class Owner>
  void load(const std::tuple<Fields...>& table, const Owner& owner, std::size_t k) {
    apply(table, [&](const auto& field, auto& entry) { entry.load(field.of(owner), k); });
  }
  template <class Owner>
  void store(const std::tuple<Fields...>& table, Owner& owner, std::size_t k) const {
    apply(table, [&](const auto& field, const auto& entry) { entry.store(field.of(owner), k); });
  }

 private:
  template <class F>
  void apply(const std::tuple<Fields...>& table, F&& f) {
    each(table, f, std::index_sequence_for<Fields...>{});
  }
  template <class F>
  void apply(const std::tuple<Fields...>& table, F&& f) const {
    each(table, f, std::index_sequence_for<Fields...>{});
  }
  template <class F, std::size_t... I>
  void each(const std::tuple<Fields...>& table, F& f, std::index_sequence<I...>) {
    (f(std::get<I>(table), std::get<I>(entries)), ...);
  }
  template <class F, std::size_t... I>
  void each(const std::tuple<Fields...>& table, F& f, std::index_sequence<I...>) const {
    (f(std::get<I>(table), std::get<I>(entries)), ...);
  }
};

}  // namespace slide
