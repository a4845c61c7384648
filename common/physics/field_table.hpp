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
#include <span>
#include <string_view>
#include <tuple>
#include <type_traits>
#include <utility>
#include <vector>

#include "common/base/error.hpp"
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

/// A permutation of rows, row k taking old row order[k], as its cycles: each cycle of two
/// or more rows is listed as r0, r1, …, rm with r(j+1) = order[rj] (row rj takes row
/// r(j+1)'s value, rm takes r0's), its last row flagged; rows that stay are left out.
/// Each column then follows the cycles on its own (`apply`), one tight loop per column
/// type: a row-by-row walk over every field per move cost ten times the instructions
/// (mpm/README.md, "Where a step's instructions go"). 4 B per moving row, beside `order`.
class RowCycles {
 public:
  /// The most rows a permutation may have (a row index's top bit flags a cycle's end).
  static constexpr std::size_t max_rows = (std::size_t{1} << 31) - 1;

  /// From `order`, a permutation of [0, n) with n ≤ max_rows; marks it (order[k] = k after).
  explicit RowCycles(std::vector<std::uint32_t>& order) {
    if (order.size() > max_rows) {
      throw Error("RowCycles: {} rows, more than {}", order.size(), max_rows);
    }
    for (std::size_t k = 0; k < order.size(); ++k) {
      if (order[k] == k) continue;
      std::size_t row = k;
      for (;;) {
        const std::size_t next = order[row];
        order[row] = static_cast<std::uint32_t>(row);
        if (next == k) {
          path_.back() |= last;
          break;
        }
        if (row == k) path_.push_back(static_cast<std::uint32_t>(k));
        path_.push_back(static_cast<std::uint32_t>(next));
        row = next;
      }
    }
  }

  template <class T>
  void apply(std::vector<T>& column) const {
    if (column.empty()) return;
    follow([&](std::size_t to, std::size_t from) { column[to] = column[from]; },
           [&](std::size_t row) { return column[row]; },
           [&](std::size_t row, const T& value) { column[row] = value; });
  }
  void apply(SurfaceStresses& column) const {
    if (column.per_point == 0) return;
    const auto copy = [](std::span<const Vec4> from, std::span<Vec4> to) {
      std::copy(from.begin(), from.end(), to.begin());
    };
    follow([&](std::size_t to, std::size_t from) { copy(column.of(from), column.of(to)); },
           [&](std::size_t row) {
             std::array<Vec4, max_yield_surfaces> saved;
             copy(column.of(row), std::span<Vec4>(saved).first(column.per_point));
             return saved;
           },
           [&](std::size_t row, const std::array<Vec4, max_yield_surfaces>& saved) {
             copy(std::span<const Vec4>(saved).first(column.per_point), column.of(row));
           });
  }

 private:
  static constexpr std::uint32_t last = std::uint32_t{1} << 31;

  /// move(to, from) along each cycle, its first row saved by save(row) and put back into
  /// the cycle's last row by restore(row, saved).
  template <class Move, class Save, class Restore>
  void follow(Move&& move, Save&& save, Restore&& restore) const {
    for (std::size_t i = 0; i < path_.size(); ++i) {
      std::size_t to = path_[i];
      const auto saved = save(to);
      for (;;) {
        const std::uint32_t entry = path_[++i];
        const std::size_t from = entry & ~last;
        move(to, from);
        to = from;
        if (entry & last) break;
      }
      restore(to, saved);
    }
  }

  std::vector<std::uint32_t> path_;
};

/// Row k of every field takes old row order[k] (`order`: a permutation of the rows, n <
/// 2³¹; marked as RowCycles leaves it), in place: no second copy of any field.
template <class Table, class Owner>
void permute_rows(const Table& table, Owner& owner, std::vector<std::uint32_t>& order) {
  const RowCycles cycles(order);
  for_each_field(table, [&](const auto& field) { cycles.apply(field.of(owner)); });
}

}  // namespace slide
