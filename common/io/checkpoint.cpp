// The checkpoint schema in code. common/io/checkpoint-schema.md documents every name written
// here; a change of name or meaning bumps checkpoint_schema_version.
//
// Layout (one field per dataset, row-major, one row per node/element/Gauss point/particle):
//   /                     attributes schema, schema_version, producer, kind, time, step,
//                         dimension, case, pe0
//   /materials/<id>/      attributes only, id = 0, 1, …
//   /nodes, /elements, /gauss_points, /boundary/<name>   kind "fem"
//   /particles, /transfer                                kinds "particles" and "mpm"
//   /solver               free-form solver settings (attributes)
//
// The writer checks what the reader checks (row counts, finite values, index ranges,
// admissible materials), so whatever it writes reads back; it stops at the first
// problem, and write_atomically then leaves the target untouched.
#include "common/io/checkpoint.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <initializer_list>
#include <limits>
#include <optional>
#include <span>
#include <type_traits>
#include <variant>

#include "common/base/error.hpp"
#include "common/base/names.hpp"
#include "common/io/atomic_file.hpp"
#include "common/io/hdf5_file.hpp"
#include "common/physics/pm4sand.hpp"

namespace slide {

namespace {

constexpr std::array<Named<CheckpointKind>, 3> kind_names{{
    {"fem", CheckpointKind::fem},
    {"particles", CheckpointKind::particles},
    {"mpm", CheckpointKind::mpm},
}};

}  // namespace

std::string_view to_string(CheckpointKind kind) {
  return name_of(kind_names, kind);
}

namespace {

namespace fs = std::filesystem;
using hdf5::Shape;
using hdf5::TypeClass;

template <int K>
using VecK = Eigen::Matrix<double, K, 1>;

/// One family of rows: what a row is called in messages, the symbol of its count in the
/// documentation, and the count (unknown while the defining dataset is being read).
struct Rows {
  const char* noun;
  const char* symbol;
  std::size_t count = 0;
  /// In a checkpoint several ranks write together: where this rank's rows go.
  const hdf5::RowShare* share = nullptr;
  /// Reading part of a file (each rank its own rows): the rows read, of `count`.
  std::optional<hdf5::RowRange> held = std::nullopt;
  /// The file row of the i-th row held (for messages).
  std::size_t row(std::size_t i) const { return held ? held->first + i : i; }
};

constexpr const char* units_attribute = "units";

// ---------------------------------------------------------------------------------------
// Checks shared by the writer and the reader. `where` is "file: /path" on reading and
// "file: cannot write /path" on writing.

void require_finite(std::string_view where, std::span<const double> values, std::size_t width,
                    const Rows& rows) {
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (!std::isfinite(values[i])) {
      throw Error("{}: {} {} is not finite ({})", where, rows.noun, rows.row(i / width), values[i]);
    }
  }
}

/// What a float dataset of a given name may hold beyond being finite: a magnitude no
/// landslide model reaches (so a number from a damaged or hand-edited file, such as a
/// strain of 4.9e226, is refused on reading, not at the end of a run), and a sign.
struct ValueRule {
  std::string_view dataset;  ///< the dataset's name, in any group
  double limit;              ///< |value| ≤ limit
  std::string_view unit;
  bool non_negative;
};

// The limits are orders of magnitude above anything physical, so no real state is
// refused: 10⁷ m is a quarter of the Earth's circumference; 10⁵ m/s is 15 times the
// P-wave speed of intact rock; 10¹² m/s² reaches that speed in one explicit step of 10⁻⁷ s;
// 10¹³ Pa is 50 times the Young's modulus of steel; a strain of 10⁶ is a
// fibre stretched a million times its length.
constexpr std::array value_rules{
    ValueRule{"reference_coordinates", 1e7, "m", false},
    ValueRule{"coordinates", 1e7, "m", false},
    ValueRule{"displacement", 1e7, "m", false},
    ValueRule{"velocity", 1e5, "m/s", false},
    ValueRule{"acceleration", 1e12, "m/s²", false},
    ValueRule{"stress", 1e13, "Pa", false},
    ValueRule{"surface_stress", 1e13, "Pa", false},
    ValueRule{"pore_pressure", 1e13, "Pa", false},
    ValueRule{"excess_pore_pressure", 1e13, "Pa", false},
    ValueRule{"initial_vertical_effective_stress", 1e13, "Pa", false},
    ValueRule{"initial_mean_effective_stress", 1e13, "Pa", false},
    ValueRule{"max_pore_pressure_ratio", 1e6, "", false},
    ValueRule{"peak_strength", 1e13, "Pa", false},
    ValueRule{"strain", 1e6, "", false},
    ValueRule{"plastic_volumetric_strain", 1e6, "", false},
    ValueRule{"eps_q", 1e6, "", true},
    ValueRule{"plastic_shear_strain", 1e6, "", true},
    ValueRule{"size", 1e7, "m", false},
};

/// Finite values, and within the dataset's ValueRule when it has one.
void require_admissible(std::string_view where, std::string_view dataset,
                        std::span<const double> values, std::size_t width, const Rows& rows) {
  require_finite(where, values, width, rows);
  const auto rule = std::find_if(value_rules.begin(), value_rules.end(),
                                 [&](const ValueRule& r) { return r.dataset == dataset; });
  if (rule == value_rules.end()) return;
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (std::abs(values[i]) > rule->limit) {
      throw Error("{}: {} {} has {}{}{}, beyond ±{:g}{}{} (no landslide reaches it: damaged data?)",
                  where, rows.noun, rows.row(i / width), values[i], rule->unit.empty() ? "" : " ",
                  rule->unit, rule->limit, rule->unit.empty() ? "" : " ", rule->unit);
    }
    if (rule->non_negative && values[i] < 0.0) {
      throw Error("{}: {} {} has {}, expected ≥ 0", where, rows.noun, rows.row(i / width),
                  values[i]);
    }
  }
}

/// The last component of a dataset path: "/particles/state/eps_q" → "eps_q".
std::string_view dataset_name(std::string_view path) {
  return path.substr(path.find_last_of('/') + 1);
}

/// Particle ids: each ≥ 0 and none twice (restarts and the tools match particles by id).
void require_unique_ids(std::string_view where, std::span<const std::int64_t> ids,
                        const Rows& rows) {
  std::vector<std::pair<std::int64_t, std::size_t>> sorted(ids.size());
  for (std::size_t i = 0; i < ids.size(); ++i) sorted[i] = {ids[i], i};
  std::sort(sorted.begin(), sorted.end());
  for (std::size_t k = 0; k < sorted.size(); ++k) {
    const auto [id, row] = sorted[k];
    if (id < 0)
      throw Error("{}: {} {} has id {}, expected ≥ 0", where, rows.noun, rows.row(row), id);
    if (k > 0 && sorted[k - 1].first == id) {
      throw Error("{}: {}s {} and {} share id {}, expected unique ids", where, rows.noun,
                  rows.row(sorted[k - 1].second), rows.row(row), id);
    }
  }
}

/// The admissible values of an index dataset, [low, high), and what bounds them.
struct IndexRange {
  static constexpr std::int64_t unbounded = std::numeric_limits<std::int64_t>::max();
  std::int64_t low = 0;
  std::int64_t high = unbounded;
  std::string_view bound;  ///< e.g. "n_nodes", shown in messages
};

/// [0, count): an index into `count` nodes, elements or materials.
IndexRange below(std::size_t count, std::string_view bound) {
  return {0, static_cast<std::int64_t>(count), bound};
}

void require_in_range(std::string_view where, std::span<const std::int64_t> values,
                      std::size_t width, const Rows& rows, const IndexRange& range) {
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (values[i] >= range.low && values[i] < range.high) continue;
    if (range.high == IndexRange::unbounded) {
      throw Error("{}: {} {} has index {}, expected ≥ {} ({})", where, rows.noun,
                  rows.row(i / width), values[i], range.low, range.bound);
    }
    throw Error("{}: {} {} has index {}, expected {} ≤ index < {} ({})", where, rows.noun,
                rows.row(i / width), values[i], range.low, range.high, range.bound);
  }
}

/// /particles/element: the source FE element, or −1 for particles of a pure MPM run.
constexpr IndexRange source_element_range{-1, IndexRange::unbounded,
                                          "−1 for pure MPM, else a source element"};
constexpr IndexRange flag_range{0, 2, "a flag: 0 or 1"};

/// The range a checkpoint holds an index column to (none: any value).
std::optional<IndexRange> index_range(Check check) {
  if (check == Check::source_element) return source_element_range;
  if (check == Check::flag) return flag_range;
  return std::nullopt;
}

void require_positive(std::string_view where, std::span<const double> values, const Rows& rows,
                      std::string_view quantity) {
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (!(values[i] > 0.0)) {
      throw Error("{}: {} {} has {} {}, expected > 0", where, rows.noun, rows.row(i), quantity,
                  values[i]);
    }
  }
}

/// Particle sizes (the domain a particle fills): both sides > 0.
void require_positive_sizes(std::string_view where, std::span<const Vec2> sizes, const Rows& rows) {
  for (std::size_t i = 0; i < sizes.size(); ++i) {
    if (!(sizes[i].x() > 0.0 && sizes[i].y() > 0.0)) {
      throw Error("{}: {} {} has size ({}, {}), expected both > 0", where, rows.noun, rows.row(i),
                  sizes[i].x(), sizes[i].y());
    }
  }
}

template <int K>
std::vector<double> flatten(std::span<const VecK<K>> vectors) {
  std::vector<double> flat(vectors.size() * K);
  for (std::size_t i = 0; i < vectors.size(); ++i) {
    for (int k = 0; k < K; ++k) flat[i * K + static_cast<std::size_t>(k)] = vectors[i][k];
  }
  return flat;
}

template <int K>
std::vector<VecK<K>> unflatten(const std::vector<double>& flat) {
  std::vector<VecK<K>> vectors(flat.size() / K);
  for (std::size_t i = 0; i < vectors.size(); ++i) {
    for (int k = 0; k < K; ++k) vectors[i][k] = flat[i * K + static_cast<std::size_t>(k)];
  }
  return vectors;
}

/// One member of every point's material state, as a column.
std::vector<double> state_column(std::span<const MaterialState> state,
                                 double MaterialState::*member) {
  std::vector<double> values(state.size());
  for (std::size_t i = 0; i < state.size(); ++i) values[i] = state[i].*member;
  return values;
}

/// The surface stresses among the fields of rows `kind` (multi-yield), or nothing.
template <class Table, class Owner>
const SurfaceStresses* surfaces_of(const Table& table, const Owner& owner, RowKind kind) {
  const SurfaceStresses* found = nullptr;
  for_each_field(table, [&](const auto& field) {
    if constexpr (std::is_same_v<typename std::remove_cvref_t<decltype(field)>::column_type,
                                 SurfaceStresses>) {
      if (field.rows == kind) found = &field.of(owner);
    }
  });
  return found;
}

/// Whether some point of rows `kind` carries multi-yield surfaces.
template <class Table, class Owner>
bool with_surfaces(const Table& table, const Owner& owner, RowKind kind) {
  const SurfaceStresses* surfaces = surfaces_of(table, owner, kind);
  return surfaces != nullptr && surfaces->per_point > 0;
}

CheckpointKind parse_kind(std::string_view text, std::string_view where) {
  for (const auto& [name, kind] : kind_names) {
    if (text == name) return kind;
  }
  throw Error("{}: attribute kind is \"{}\", expected {}", where, text, quoted_names(kind_names));
}

// ---------------------------------------------------------------------------------------
// Attributes of a struct, listed once for the writer and the reader

template <class T>
struct Attribute {
  std::string_view name;
  std::variant<double T::*, std::string T::*, std::int64_t T::*> member;
};

/// A material's numbers (its names and the multi-yield constants are written apart).
constexpr std::array<Attribute<Material>, 7> material_numbers{{
    {"density", &Material::density},
    {"youngs_modulus", &Material::youngs_modulus},
    {"poisson_ratio", &Material::poisson_ratio},
    {"friction_angle", &Material::friction_angle},
    {"cohesion", &Material::cohesion},
    {"dilation_angle", &Material::dilation_angle},
    {"tension_cutoff", &Material::tension_cutoff},
}};

/// A porous material's (docs/method.md §10).
constexpr std::array<Attribute<Material>, 3> pore_water_numbers{{
    {"porosity", &Material::porosity},
    {"conductivity_x", &Material::conductivity_x},
    {"conductivity_y", &Material::conductivity_y},
}};

/// PM4Sand's parameters (model "pm4sand" only), as attributes pm4sand_<name>, every
/// default resolved from D_R; a_do and z_max only when given (otherwise each point
/// derives them at the switch and keeps them in its state records).
constexpr std::array<Attribute<Pm4SandParameters>, 21> pm4sand_numbers{{
    {"pm4sand_relative_density", &Pm4SandParameters::relative_density},
    {"pm4sand_shear_modulus_coefficient", &Pm4SandParameters::shear_modulus_coefficient},
    {"pm4sand_contraction_rate", &Pm4SandParameters::contraction_rate},
    {"pm4sand_atmospheric_pressure", &Pm4SandParameters::atmospheric_pressure},
    {"pm4sand_h0", &Pm4SandParameters::h0},
    {"pm4sand_e_max", &Pm4SandParameters::e_max},
    {"pm4sand_e_min", &Pm4SandParameters::e_min},
    {"pm4sand_n_b", &Pm4SandParameters::n_b},
    {"pm4sand_n_d", &Pm4SandParameters::n_d},
    {"pm4sand_c_z", &Pm4SandParameters::c_z},
    {"pm4sand_c_e", &Pm4SandParameters::c_e},
    {"pm4sand_critical_friction_angle", &Pm4SandParameters::critical_friction_angle},
    {"pm4sand_c_gd", &Pm4SandParameters::c_gd},
    {"pm4sand_c_dr", &Pm4SandParameters::c_dr},
    {"pm4sand_c_kaf", &Pm4SandParameters::c_kaf},
    {"pm4sand_q", &Pm4SandParameters::q},
    {"pm4sand_r", &Pm4SandParameters::r},
    {"pm4sand_m", &Pm4SandParameters::m},
    {"pm4sand_strain_step", &Pm4SandParameters::strain_step},
    {"pm4sand_a_do", &Pm4SandParameters::a_do},
    {"pm4sand_z_max", &Pm4SandParameters::z_max},
}};
/// The last two of pm4sand_numbers are optional.
constexpr std::size_t pm4sand_required = pm4sand_numbers.size() - 2;

/// The parameters with every default derived from D_R written out (pm4sand::Constants).
Pm4SandParameters resolved(const Material& m) {
  const pm4sand::Constants c = pm4sand::Constants::of(m);
  Pm4SandParameters p = m.pm4sand;
  p.shear_modulus_coefficient = c.g0;
  p.h0 = c.h0;
  p.c_e = c.c_e;
  p.c_dr = c.c_dr;
  p.c_kaf = c.c_kaf;
  return p;
}

void write_pm4sand(hdf5::Group& g, const Material& m) {
  const Pm4SandParameters p = resolved(m);
  for (std::size_t i = 0; i < pm4sand_numbers.size(); ++i) {
    const double value = p.*std::get<double Pm4SandParameters::*>(pm4sand_numbers[i].member);
    if (i >= pm4sand_required && std::isnan(value)) continue;
    g.write_double_attribute(pm4sand_numbers[i].name, value);
  }
}

void read_pm4sand(const hdf5::Group& g, Material& m) {
  for (std::size_t i = 0; i < pm4sand_numbers.size(); ++i) {
    const auto member = std::get<double Pm4SandParameters::*>(pm4sand_numbers[i].member);
    if (i >= pm4sand_required && !g.has_attribute(pm4sand_numbers[i].name)) continue;
    m.pm4sand.*member = g.read_double_attribute(pm4sand_numbers[i].name);
  }
}

/// A material's liquefaction rule and residual strength (docs/method.md §10), as
/// attributes liquefaction_<name> beside liquefaction_correlation; unset (NaN) values are
/// left out.
constexpr std::array<Attribute<LiquefactionParameters>, 10> liquefaction_numbers{{
    {"liquefaction_pore_pressure_ratio", &LiquefactionParameters::pore_pressure_ratio},
    {"liquefaction_shear_strain", &LiquefactionParameters::shear_strain},
    {"liquefaction_blow_count", &LiquefactionParameters::blow_count},
    {"liquefaction_strength_ratio", &LiquefactionParameters::strength_ratio},
    {"liquefaction_friction_angle", &LiquefactionParameters::friction_angle},
    {"liquefaction_minimum_strength", &LiquefactionParameters::minimum_strength},
    {"liquefaction_peak_strength_ratio", &LiquefactionParameters::peak_strength_ratio},
    {"liquefaction_softening_strain", &LiquefactionParameters::softening_strain},
    {"liquefaction_shear_modulus_ratio", &LiquefactionParameters::shear_modulus_ratio},
    {"liquefaction_poisson_ratio", &LiquefactionParameters::poisson_ratio},
}};

void write_liquefaction(hdf5::Group& g, const LiquefactionParameters& q) {
  g.write_string_attribute("liquefaction_correlation", to_string(q.correlation));
  for (const auto& a : liquefaction_numbers) {
    const double value = q.*std::get<double LiquefactionParameters::*>(a.member);
    if (!std::isnan(value)) g.write_double_attribute(a.name, value);
  }
}

void read_liquefaction(const hdf5::Group& g, LiquefactionParameters& q) {
  q.enabled = true;
  q.correlation = parse_residual_strength_correlation(
      g.read_string_attribute("liquefaction_correlation"),
      fmt::format("{}: attribute liquefaction_correlation", g.where()));
  for (const auto& a : liquefaction_numbers) {
    double& value = q.*std::get<double LiquefactionParameters::*>(a.member);
    value =
        g.has_attribute(a.name) ? g.read_double_attribute(a.name) : LiquefactionParameters::unset;
  }
}

/// How fem2mpm made the particles (/transfer).
constexpr std::array<Attribute<TransferSettings>, 6> transfer_attributes{{
    {"transfer_time", &TransferSettings::transfer_time},
    {"particles_per_element", &TransferSettings::particles_per_element},
    {"stress_interpolation", &TransferSettings::stress_interpolation},
    {"rbf_polynomial", &TransferSettings::rbf_polynomial},
    {"rbf_shape", &TransferSettings::rbf_shape},
    {"rbf_neighbours", &TransferSettings::rbf_neighbours},
}};

template <class T, std::size_t N>
void write_attributes(hdf5::Group& group, const T& object,
                      const std::array<Attribute<T>, N>& attributes) {
  for (const Attribute<T>& a : attributes) {
    std::visit(
        [&](auto member) {
          const auto& value = object.*member;
          using V = std::remove_cvref_t<decltype(value)>;
          if constexpr (std::is_same_v<V, double>) {
            group.write_double_attribute(a.name, value);
          } else if constexpr (std::is_same_v<V, std::string>) {
            group.write_string_attribute(a.name, value);
          } else {
            group.write_int_attribute(a.name, value);
          }
        },
        a.member);
  }
}

template <class T, std::size_t N>
void read_attributes(const hdf5::Group& group, T& object,
                     const std::array<Attribute<T>, N>& attributes) {
  for (const Attribute<T>& a : attributes) {
    std::visit(
        [&](auto member) {
          auto& value = object.*member;
          using V = std::remove_cvref_t<decltype(value)>;
          if constexpr (std::is_same_v<V, double>) {
            value = group.read_double_attribute(a.name);
          } else if constexpr (std::is_same_v<V, std::string>) {
            value = group.read_string_attribute(a.name);
          } else {
            value = group.read_int_attribute(a.name);
          }
        },
        a.member);
  }
}

// ---------------------------------------------------------------------------------------
// Writing

/// Which unused particle fields ranks writing together hold: APIC's affine velocity and
/// the saturated transfer's fields (every rank says the same, also one without particles).
struct UsedFields {
  bool affine = false;
  bool pore_water = false;
  bool of(std::string_view name) const {
    return name == "affine_velocity_gradient" ? affine : pore_water;
  }
};

class Writer {
 public:
  Writer(hdf5::File& file, std::string target) : file_(file), target_(std::move(target)) {}

  hdf5::File& file() { return file_; }
  const std::string& target() const { return target_; }

  std::string where(const hdf5::Group& group, std::string_view name) const {
    if (name.empty()) return fmt::format("{}: cannot write {}", target_, group.path());
    return fmt::format("{}: cannot write {}{}{}", target_, group.path(),
                       group.path() == "/" ? "" : "/", name);
  }

  /// n×width floats (width 0: a 1-D dataset of n values).
  void doubles(hdf5::Group& group, std::string_view name, std::span<const double> values,
               std::size_t width, const Rows& rows, std::string_view units) {
    const std::string at = where(group, name);
    require_count(at, values.size(), width, rows);
    require_admissible(at, name, values, std::max<std::size_t>(width, 1), rows);
    group.write_dataset(name, values, shape(width, rows), rows.share)
        .write_string_attribute(units_attribute, units);
  }

  template <int K>
  void vectors(hdf5::Group& group, std::string_view name, const std::vector<VecK<K>>& values,
               const Rows& rows, std::string_view units) {
    require_count(where(group, name), values.size(), 0, rows);
    doubles(group, name, flatten<K>(values), K, rows, units);
  }

  /// n×width int64 indices (width 0: 1-D), each in `range` when one is given.
  hdf5::Dataset indices(hdf5::Group& group, std::string_view name,
                        std::span<const std::int64_t> values, std::size_t width, const Rows& rows,
                        const std::optional<IndexRange>& range) {
    const std::string at = where(group, name);
    require_count(at, values.size(), width, rows);
    if (range) require_in_range(at, values, std::max<std::size_t>(width, 1), rows, *range);
    hdf5::Dataset dataset = group.write_dataset(name, values, shape(width, rows), rows.share);
    dataset.write_string_attribute(units_attribute, "1");
    return dataset;
  }

  void material_ids(hdf5::Group& group, const std::vector<std::int32_t>& ids, const Rows& rows,
                    std::size_t material_count) {
    const std::string at = where(group, "material_id");
    require_count(at, ids.size(), 0, rows);
    const std::vector<std::int64_t> wide(ids.begin(), ids.end());
    require_in_range(at, wide, 1, rows, below(material_count, "materials in /materials"));
    group.write_dataset("material_id", ids, shape(0, rows), rows.share)
        .write_string_attribute(units_attribute, "1");
  }

  /// Every field of `table` with rows `kind` into `group` (and its state/ subgroup). An
  /// unused field (Presence::when_used) is written when it is set, or as `when_used`
  /// says for it (ranks writing together, some of them without particles).
  template <class Table, class Owner>
  void fields(hdf5::Group& group, const Table& table, const Owner& owner, RowKind kind,
              const Rows& rows, std::size_t material_count,
              std::optional<UsedFields> when_used = std::nullopt) {
    const bool surfaces = with_surfaces(table, owner, kind);
    for_each_field(table, [&](const auto& field) {
      if (field.rows != kind) return;
      const auto& values = field.of(owner);
      if constexpr (std::is_same_v<std::remove_cvref_t<decltype(values)>, SurfaceStresses>) {
        if (values.per_point > 0) surface_column(group, values, rows);
      } else {
        if (field.presence == Presence::when_used &&
            !(when_used ? when_used->of(field.name) : !values.empty())) {
          return;
        }
        column(group, field, values, rows, material_count, surfaces);
      }
    });
  }

 private:
  /// The state/ subgroup of `parent`, created when it is not there yet.
  static hdf5::Group state_group(hdf5::Group& parent) {
    return parent.contains("state") ? parent.open_group("state") : parent.create_group("state");
  }

  template <class FieldT, class T>
  void column(hdf5::Group& group, const FieldT& field, const std::vector<T>& values,
              const Rows& rows, std::size_t material_count, bool surfaces) {
    const std::string_view name = field.name;
    if constexpr (std::is_same_v<T, double>) {
      if (field.check == Check::positive) require_positive(where(group, name), values, rows, name);
      doubles(group, name, values, 0, rows, field.unit);
    } else if constexpr (std::is_same_v<T, std::int32_t>) {
      material_ids(group, values, rows, material_count);
    } else if constexpr (std::is_same_v<T, std::int64_t>) {
      if (field.check == Check::unique_id) require_unique_ids(where(group, name), values, rows);
      indices(group, name, values, 0, rows, index_range(field.check));
    } else if constexpr (std::is_same_v<T, MaterialState>) {
      require_count(where(group, name), values.size(), 0, rows);
      hdf5::Group state = state_group(group);
      for (const StateField& member : material_state_fields) {
        if (member.presence == StatePresence::with_surfaces && !surfaces) continue;
        doubles(state, member.name, state_column(values, member.member), 0, rows, member.unit);
      }
    } else {
      if constexpr (std::is_same_v<T, Vec2>) {
        if (field.check == Check::positive_size)
          require_positive_sizes(where(group, name), values, rows);
      }
      vectors<T::RowsAtCompileTime>(group, name, values, rows, field.unit);
    }
  }

  /// The multi-yield surfaces, [sxx, syy, szz, sxy] per surface, n × 4·per_point.
  void surface_column(hdf5::Group& group, const SurfaceStresses& surfaces, const Rows& rows) {
    std::vector<double> flat(surfaces.values.size() * 4);
    for (std::size_t i = 0; i < surfaces.values.size(); ++i) {
      for (int k = 0; k < 4; ++k) flat[4 * i + static_cast<std::size_t>(k)] = surfaces.values[i][k];
    }
    hdf5::Group state = state_group(group);
    doubles(state, "surface_stress", flat, 4 * surfaces.per_point, rows, "Pa");
  }

  static Shape shape(std::size_t width, const Rows& rows) {
    return width == 0 ? Shape{rows.count} : Shape{rows.count, width};
  }

  static void require_count(std::string_view where, std::size_t values, std::size_t width,
                            const Rows& rows) {
    const std::size_t expected = rows.count * std::max<std::size_t>(width, 1);
    if (values != expected) {
      throw Error("{}: {} entries, expected {} ({} per {})", where, values, expected,
                  width > 1 ? std::to_string(width) : std::string("one"), rows.noun);
    }
  }

  hdf5::File& file_;
  std::string target_;
};

void write_header(hdf5::File& file, const CheckpointHeader& header, CheckpointKind kind) {
  file.write_string_attribute("schema", checkpoint_schema_name);
  file.write_int_attribute("schema_version", checkpoint_schema_version);
  file.write_string_attribute("producer", header.producer);
  file.write_string_attribute("kind", to_string(kind));
  file.write_double_attribute("time", header.time);
  file.write_int_attribute("step", header.step);
  file.write_int_attribute("dimension", 2);
  file.write_string_attribute("case", header.case_name);
  file.write_double_attribute("pe0", header.pe0);
}

void check_header(std::string_view target, const CheckpointHeader& header) {
  if (!std::isfinite(header.time))
    throw Error("{}: cannot write: time {} is not finite", target, header.time);
  if (!std::isfinite(header.pe0))
    throw Error("{}: cannot write: pe0 {} is not finite", target, header.pe0);
  if (header.step < 0) throw Error("{}: cannot write: step {} is negative", target, header.step);
}

void write_materials(Writer& writer, const MaterialTable& materials) {
  hdf5::Group group = writer.file().create_group("materials");
  for (std::size_t id = 0; id < materials.size(); ++id) {
    const Material& m = materials[id];
    m.validate(writer.where(group, std::to_string(id)));
    hdf5::Group g = group.create_group(std::to_string(id));
    g.write_string_attribute("name", m.name);
    g.write_string_attribute("model", to_string(m.model));
    g.write_string_attribute("mpm_model", to_string(m.model_of(Phase::mpm)));
    if (m.uses(MaterialModel::pressure_independent_multi_yield)) {
      g.write_double_attribute("peak_shear_strain", m.peak_shear_strain);
      g.write_int_attribute("yield_surfaces", m.yield_surfaces);
    }
    if (m.uses(MaterialModel::pm4sand)) write_pm4sand(g, m);
    // Porous materials only (schema version 6): dry ones keep the attributes they had.
    if (m.saturable()) write_attributes(g, m, pore_water_numbers);
    if (m.liquefaction.enabled) write_liquefaction(g, m.liquefaction);
    write_attributes(g, m, material_numbers);
  }
}

void write_solver(Writer& writer, const SolverSettings& solver) {
  hdf5::Group group = writer.file().create_group("solver");
  for (const auto& [key, value] : solver) {
    if (key.empty()) throw Error("{}: a solver setting has an empty name", writer.where(group, ""));
    std::visit(
        [&](const auto& v) {
          using T = std::decay_t<decltype(v)>;
          if constexpr (std::is_same_v<T, std::int64_t>) {
            group.write_int_attribute(key, v);
          } else if constexpr (std::is_same_v<T, double>) {
            group.write_double_attribute(key, v);
          } else {
            group.write_string_attribute(key, v);
          }
        },
        value);
  }
}

void write_boundary(Writer& writer, const FemCheckpoint& c, const Rows& nodes) {
  hdf5::Group group = writer.file().create_group("boundary");
  if (!std::isfinite(c.friction_coefficient) || c.friction_coefficient < 0.0) {
    throw Error("{}: friction_coefficient {} is not a finite value ≥ 0", writer.where(group, ""),
                c.friction_coefficient);
  }
  group.write_double_attribute("friction_coefficient", c.friction_coefficient);
  const auto& sets = c.mesh.node_sets;
  if (c.boundary_conditions.size() != sets.size()) {
    throw Error("{}: {} boundary conditions for {} node sets", writer.where(group, ""),
                c.boundary_conditions.size(), sets.size());
  }
  for (std::size_t i = 0; i < sets.size(); ++i) {
    const NodeSet& set = sets[i];
    if (set.name.empty() || set.name == "." || set.name.find('/') != std::string::npos ||
        group.contains(set.name)) {
      throw Error("{}: node set name \"{}\" is empty, repeated or contains '/'",
                  writer.where(group, set.name), set.name);
    }
    hdf5::Group g = group.create_group(set.name);
    const std::array<double, 2> normal{set.normal.x(), set.normal.y()};
    if (!std::isfinite(normal[0]) || !std::isfinite(normal[1])) {
      throw Error("{}: normal is not finite", writer.where(group, set.name));
    }
    g.write_int_attribute("index", static_cast<std::int64_t>(i));
    g.write_string_attribute("condition", to_string(c.boundary_conditions[i]));
    g.write_double_array_attribute("normal", normal);
    const Rows set_rows{"entry", "n_set", set.nodes.size()};
    writer.indices(g, "nodes", set.nodes, 0, set_rows, below(nodes.count, "n_nodes"));
  }
}

void write_motion(Writer& writer, const std::optional<CheckpointMotion>& motion) {
  if (!motion) return;
  const CheckpointMotion& m = *motion;
  if (!std::isfinite(m.start_time) || !(m.step > 0.0) || !std::isfinite(m.step)) {
    throw Error("{}: cannot write /motion: start_time {} s, step {} s", writer.target(),
                m.start_time, m.step);
  }
  hdf5::Group g = writer.file().create_group("motion");
  g.write_double_attribute("start_time", m.start_time);
  g.write_double_attribute("step", m.step);
  g.write_string_attribute("base", m.base);
  g.write_string_attribute("input", m.input);
  if (!m.base_displacement.allFinite() || !std::isfinite(m.base_time)) {
    throw Error("{}: cannot write /motion: base displacement or time not finite", writer.target());
  }
  g.write_double_attribute("base_time", m.base_time);
  g.write_double_attribute("base_displacement_x", m.base_displacement.x());
  g.write_double_attribute("base_displacement_y", m.base_displacement.y());
  if (!std::isnan(m.record_end_time)) {
    g.write_double_attribute("record_end_time", m.record_end_time);
  }
  const Rows samples{"sample", "n_samples", m.acceleration.size()};
  writer.vectors<2>(g, "acceleration", m.acceleration, samples, "m/s^2");
  writer.vectors<2>(g, "velocity", m.velocity, samples, "m/s");
  writer.vectors<2>(g, "displacement", m.displacement, samples, "m");
}

void write_fem(Writer& writer, const FemCheckpoint& c) {
  hdf5::File& file = writer.file();
  write_header(file, c.header, CheckpointKind::fem);
  write_materials(writer, c.materials);

  const Mesh& mesh = c.mesh;
  const Rows nodes{"node", "n_nodes", mesh.nodes.size()};
  const Rows elements{"element", "n_elements", mesh.material_id.size()};
  const Rows gauss{"Gauss point", "n_gp", c.gauss_element.size()};

  hdf5::Group n = file.create_group("nodes");
  writer.vectors<2>(n, "reference_coordinates", mesh.nodes, nodes, "m");
  writer.vectors<2>(n, "coordinates", c.coordinates, nodes, "m");
  writer.fields(n, fe_fields, c, RowKind::node, nodes, c.materials.size());

  hdf5::Group e = file.create_group("elements");
  hdf5::Dataset connectivity = writer.indices(e, "connectivity", mesh.connectivity,
                                              static_cast<std::size_t>(mesh.nodes_per_element()),
                                              elements, below(nodes.count, "n_nodes"));
  connectivity.write_string_attribute("type", to_string(mesh.shape()));
  connectivity.write_string_attribute("integration", to_string(mesh.element_type));
  writer.material_ids(e, mesh.material_id, elements, c.materials.size());
  writer.doubles(e, "jacobian_ratio", c.jacobian_ratio, 0, elements, "1");
  if (!c.scaled_jacobian.empty()) {
    writer.doubles(e, "scaled_jacobian", c.scaled_jacobian, 0, elements, "1");
  }
  require_positive(writer.where(e, "volume_reference"), c.volume_reference, elements,
                   "reference volume");
  writer.doubles(e, "volume_reference", c.volume_reference, 0, elements, "m^3/m");
  writer.doubles(e, "volume", c.volume, 0, elements, "m^3/m");
  writer.fields(e, fe_fields, c, RowKind::element, elements, c.materials.size());

  hdf5::Group g = file.create_group("gauss_points");
  writer.indices(g, "element", c.gauss_element, 0, gauss, below(elements.count, "n_elements"));
  writer.vectors<2>(g, "local_coordinates", c.gauss_local_coordinates, gauss, "1");
  writer.vectors<2>(g, "coordinates", c.gauss_coordinates, gauss, "m");
  require_positive(writer.where(g, "weight"), c.gauss_weight, gauss, "weight");
  writer.doubles(g, "weight", c.gauss_weight, 0, gauss, "1");
  writer.doubles(g, "eps_q", c.eps_q, 0, gauss, "1");
  writer.fields(g, fe_fields, c, RowKind::gauss_point, gauss, c.materials.size());

  write_boundary(writer, c, nodes);
  write_solver(writer, c.solver);
  write_motion(writer, c.motion);
}

void write_transfer(Writer& writer, const TransferSettings& t) {
  if (!std::isfinite(t.transfer_time) || !std::isfinite(t.rbf_shape)) {
    throw Error("{}: cannot write /transfer: transfer_time and rbf_shape must be finite",
                writer.target());
  }
  hdf5::Group group = writer.file().create_group("transfer");
  write_attributes(group, t, transfer_attributes);
}

bool is_default(const TransferSettings& t) {
  const TransferSettings d;
  return t.transfer_time == d.transfer_time && t.particles_per_element == d.particles_per_element &&
         t.stress_interpolation == d.stress_interpolation && t.rbf_polynomial == d.rbf_polynomial &&
         t.rbf_shape == d.rbf_shape && t.rbf_neighbours == d.rbf_neighbours;
}

/// `share`: this rank's rows when several write the file together; `affine`: whether
/// the particles carry APIC's C_p (only an APIC run writes it), on every rank.
void write_particles(Writer& writer, const ParticleCheckpoint& c,
                     const hdf5::RowShare* share = nullptr, std::optional<UsedFields> affine = {}) {
  hdf5::File& file = writer.file();
  write_header(file, c.header, c.header.kind);
  write_materials(writer, c.materials);

  const Particles& p = c.particles;
  const Rows particles{"particle", "n_p", p.coordinates.size(), share};
  hdf5::Group g = file.create_group("particles");
  // `affine`: whether the particles carry C_p (on every rank, also one without particles).
  writer.fields(g, particle_fields, p, RowKind::particle, particles, c.materials.size(), affine);

  if (c.header.kind == CheckpointKind::particles || !is_default(c.transfer)) {
    write_transfer(writer, c.transfer);
  }
  write_solver(writer, c.solver);
  write_motion(writer, c.motion);
}

// ---------------------------------------------------------------------------------------
// Reading

class Reader {
 public:
  explicit Reader(const fs::path& path) : file_(hdf5::File::open(path)) {}

  const hdf5::File& file() const { return file_; }
  const std::string& label() const { return file_.file_label(); }
  std::string where(std::string_view path) const { return fmt::format("{}: {}", label(), path); }

  /// The number of rows of the dataset that defines a family (e.g. n_nodes from
  /// /nodes/reference_coordinates), after checking its type class and columns.
  Rows define_rows(std::string_view path, TypeClass type_class, std::size_t width, const char* noun,
                   const char* symbol) const {
    const hdf5::Dataset dataset = file_.open_dataset(relative(path));
    require_type_class(dataset, type_class);
    const Shape shape = dataset.shape();
    if (shape.size() != (width == 0 ? 1u : 2u) || (width > 0 && shape[1] != width)) {
      throw Error("{}: shape {}, expected {}{}", where(path), hdf5::format_shape(shape), symbol,
                  width > 0 ? fmt::format("×{}", width) : std::string());
    }
    return Rows{noun, symbol, shape[0]};
  }

  /// n×width floats (width 0: 1-D), checked for shape and finite values.
  std::vector<double> doubles(std::string_view path, std::size_t width, const Rows& rows) const {
    const hdf5::Dataset dataset = open(path, TypeClass::floating_point, width, rows);
    std::vector<double> values = dataset.read_doubles(rows.held);
    require_admissible(where(path), dataset_name(path), values, std::max<std::size_t>(width, 1),
                       rows);
    return values;
  }

  template <int K>
  std::vector<VecK<K>> vectors(std::string_view path, const Rows& rows) const {
    return unflatten<K>(doubles(path, K, rows));
  }

  /// n×width integers (width 0: 1-D), each in `range` when one is given.
  std::vector<std::int64_t> indices(std::string_view path, std::size_t width, const Rows& rows,
                                    const std::optional<IndexRange>& range) const {
    const hdf5::Dataset dataset = open(path, TypeClass::integer, width, rows);
    std::vector<std::int64_t> values = dataset.read_int64(rows.held);
    if (range) require_in_range(where(path), values, std::max<std::size_t>(width, 1), rows, *range);
    return values;
  }

  std::vector<std::int32_t> material_ids(std::string_view path, const Rows& rows,
                                         std::size_t material_count) const {
    const std::vector<std::int64_t> wide =
        indices(path, 0, rows, below(material_count, "materials in /materials"));
    return std::vector<std::int32_t>(wide.begin(), wide.end());  // in range: fits
  }

  /// Every field of `table` with rows `kind` from the group `group` (e.g. "/particles"),
  /// checked; an unused field (Presence::when_used) and the multi-yield surfaces when the
  /// file has them, else left empty.
  template <class Table, class Owner>
  void fields(const Table& table, Owner& owner, RowKind kind, std::string_view group,
              const Rows& rows, std::size_t material_count) const {
    for_each_field(table, [&](const auto& field) {
      if (field.rows != kind) return;
      auto& values = field.of(owner);
      const std::string path = fmt::format("{}/{}", group, field.name);
      if constexpr (std::is_same_v<std::remove_cvref_t<decltype(values)>, SurfaceStresses>) {
        values = surface_stress(path, rows);
      } else {
        if (field.presence == Presence::when_used && !file_.contains(relative(path))) return;
        column(field, values, path, rows, material_count);
      }
    });
  }

 private:
  template <class FieldT, class T>
  void column(const FieldT& field, std::vector<T>& values, const std::string& path,
              const Rows& rows, std::size_t material_count) const {
    if constexpr (std::is_same_v<T, double>) {
      values = doubles(path, 0, rows);
      if (field.check == Check::positive) require_positive(where(path), values, rows, field.name);
    } else if constexpr (std::is_same_v<T, std::int32_t>) {
      values = material_ids(path, rows, material_count);
    } else if constexpr (std::is_same_v<T, std::int64_t>) {
      values = indices(path, 0, rows, index_range(field.check));
      if (field.check == Check::unique_id) require_unique_ids(where(path), values, rows);
    } else if constexpr (std::is_same_v<T, MaterialState>) {
      values.assign(rows.held ? rows.held->count : rows.count, MaterialState{});
      for (const StateField& member : material_state_fields) {
        const std::string column_path = fmt::format("{}/{}", path, member.name);
        // Only multi-yield runs store the frozen peak strength.
        if (member.presence == StatePresence::with_surfaces &&
            !file_.contains(relative(column_path)))
          continue;
        const std::vector<double> read = doubles(column_path, 0, rows);
        for (std::size_t i = 0; i < values.size(); ++i) values[i].*member.member = read[i];
      }
    } else {
      values = vectors<T::RowsAtCompileTime>(path, rows);
      if constexpr (std::is_same_v<T, Vec2>) {
        if (field.check == Check::positive_size) require_positive_sizes(where(path), values, rows);
      }
    }
  }

  /// The multi-yield surface stresses, if the file has them (n × 4·surfaces).
  SurfaceStresses surface_stress(const std::string& path, const Rows& rows) const {
    SurfaceStresses surfaces;
    if (!file_.contains(relative(path))) return surfaces;
    const hdf5::Shape shape = file_.open_dataset(relative(path)).shape();
    const std::size_t width = shape.size() == 2 ? shape[1] : 0;
    if (width == 0 || width % 4 != 0 || width > 4 * max_yield_surfaces) {
      throw Error("{}: shape {}, expected {} × 4·k (k ≤ {} surfaces)", where(path),
                  hdf5::format_shape(shape), rows.count, max_yield_surfaces);
    }
    const std::vector<double> flat = doubles(path, width, rows);
    surfaces.per_point = width / 4;
    surfaces.values = unflatten<4>(flat);
    return surfaces;
  }

  static std::string_view relative(std::string_view path) { return path.substr(1); }

  void require_type_class(const hdf5::Dataset& dataset, TypeClass expected) const {
    const TypeClass actual = dataset.type_class();
    if (actual != expected) {
      throw Error("{}: type class {}, expected {}", dataset.where(), hdf5::to_string(actual),
                  hdf5::to_string(expected));
    }
  }

  hdf5::Dataset open(std::string_view path, TypeClass type_class, std::size_t width,
                     const Rows& rows) const {
    hdf5::Dataset dataset = file_.open_dataset(relative(path));
    require_type_class(dataset, type_class);
    const Shape expected = width == 0 ? Shape{rows.count} : Shape{rows.count, width};
    const Shape actual = dataset.shape();
    if (actual != expected) {
      throw Error("{}: shape {}, expected {}", where(path), hdf5::format_shape(actual),
                  hdf5::format_shape(expected));
    }
    return dataset;
  }

  hdf5::File file_;
};

CheckpointHeader read_header(const hdf5::File& file) {
  const std::string& label = file.file_label();
  if (!file.has_attribute("schema")) {
    throw Error("{}: attribute schema missing: not a {} file", label, checkpoint_schema_name);
  }
  const std::string schema = file.read_string_attribute("schema");
  if (schema != checkpoint_schema_name) {
    throw Error("{}: attribute schema is \"{}\", expected \"{}\"", label, schema,
                checkpoint_schema_name);
  }
  CheckpointHeader header;
  header.schema_version = file.read_int_attribute("schema_version");
  if (header.schema_version > checkpoint_schema_version) {
    throw Error(
        "{}: schema_version {} is newer than this program reads (schema_version {}): use a newer "
        "version of the programs",
        label, header.schema_version, checkpoint_schema_version);
  }
  if (header.schema_version < oldest_checkpoint_schema_version) {
    throw Error("{}: unknown schema_version {}, expected {} to {}", label, header.schema_version,
                oldest_checkpoint_schema_version, checkpoint_schema_version);
  }
  header.kind = parse_kind(file.read_string_attribute("kind"), label);
  const std::int64_t dimension = file.read_int_attribute("dimension");
  if (dimension != 2) {
    throw Error("{}: attribute dimension is {}, expected 2 (plane strain)", label, dimension);
  }
  header.producer = file.read_string_attribute("producer");
  header.case_name = file.read_string_attribute("case");
  header.time = file.read_double_attribute("time");
  if (!std::isfinite(header.time)) {
    throw Error("{}: attribute time is {}, expected a finite number", label, header.time);
  }
  header.step = file.read_int_attribute("step");
  if (header.step < 0) throw Error("{}: attribute step is {}, expected ≥ 0", label, header.step);
  header.pe0 = file.read_double_attribute("pe0");
  if (!std::isfinite(header.pe0)) {
    throw Error("{}: attribute pe0 is {}, expected a finite number", label, header.pe0);
  }
  return header;
}

/// The first of `members` that is not one of "0", "1", …, "n−1" (n = members.size()).
std::string stray_member(const std::vector<std::string>& members) {
  for (const std::string& member : members) {
    bool numbered = false;
    for (std::size_t id = 0; id < members.size() && !numbered; ++id) {
      numbered = member == std::to_string(id);
    }
    if (!numbered) return member;
  }
  return {};
}

MaterialTable read_materials(const Reader& reader) {
  const hdf5::Group group = reader.file().open_group("materials");
  const std::vector<std::string> members = group.member_names();
  MaterialTable materials(members.size());
  // Groups are named 0, 1, …, n−1: any other name means a gap or a stray member.
  for (std::size_t id = 0; id < materials.size(); ++id) {
    if (!group.contains(std::to_string(id))) {
      throw Error("{}: expected groups 0…{} (one per material), found \"{}\"", group.where(),
                  materials.size() - 1, stray_member(members));
    }
    const hdf5::Group g = group.open_group(std::to_string(id));
    Material& m = materials[id];
    m.name = g.read_string_attribute("name");
    m.model = parse_material_model(g.read_string_attribute("model"),
                                   fmt::format("{}: attribute model", g.where()));
    read_attributes(g, m, material_numbers);
    if (g.has_attribute("porosity")) read_attributes(g, m, pore_water_numbers);
    // Files of schema version 1 name one model for both phases.
    if (g.has_attribute("mpm_model")) {
      const MaterialModel mpm = parse_material_model(
          g.read_string_attribute("mpm_model"), fmt::format("{}: attribute mpm_model", g.where()));
      if (mpm != m.model) m.mpm_model = mpm;
    }
    if (m.uses(MaterialModel::pressure_independent_multi_yield)) {
      m.peak_shear_strain = g.read_double_attribute("peak_shear_strain");
      const std::int64_t surfaces = g.read_int_attribute("yield_surfaces");
      if (surfaces < 1 || surfaces > max_yield_surfaces) {
        throw Error("{}: attribute yield_surfaces = {} (expected 1 to {})", g.where(), surfaces,
                    max_yield_surfaces);
      }
      m.yield_surfaces = static_cast<int>(surfaces);
    }
    if (m.uses(MaterialModel::pm4sand)) read_pm4sand(g, m);
    if (g.has_attribute("liquefaction_correlation")) read_liquefaction(g, m.liquefaction);
    m.validate(g.where());
  }
  return materials;
}

SolverSettings read_solver(const Reader& reader) {
  SolverSettings solver;
  if (!reader.file().contains("solver")) return solver;  // optional: no settings
  const hdf5::Group group = reader.file().open_group("solver");
  for (const std::string& key : group.attribute_names()) {
    switch (group.attribute_type_class(key)) {
      case TypeClass::integer:
        solver[key] = group.read_int_attribute(key);
        break;
      case TypeClass::floating_point:
        solver[key] = group.read_double_attribute(key);
        break;
      case TypeClass::string:
        solver[key] = group.read_string_attribute(key);
        break;
      case TypeClass::other:
        throw Error("{}: attribute {}: expected an integer, a number or a string", group.where(),
                    key);
    }
  }
  return solver;
}

void read_boundary(const Reader& reader, FemCheckpoint& c, const Rows& nodes) {
  const hdf5::Group group = reader.file().open_group("boundary");
  c.friction_coefficient = group.read_double_attribute("friction_coefficient");
  if (!std::isfinite(c.friction_coefficient) || c.friction_coefficient < 0.0) {
    throw Error("{}: attribute friction_coefficient is {}, expected a finite value ≥ 0",
                group.where(), c.friction_coefficient);
  }
  const std::vector<std::string> names = group.member_names();
  c.mesh.node_sets.assign(names.size(), NodeSet{});
  c.boundary_conditions.assign(names.size(), BoundaryCondition::free);
  std::vector<bool> seen(names.size(), false);
  for (const std::string& name : names) {
    const hdf5::Group g = group.open_group(name);
    const std::int64_t index = g.read_int_attribute("index");
    if (index < 0 || index >= static_cast<std::int64_t>(names.size()) ||
        seen[static_cast<std::size_t>(index)]) {
      throw Error("{}: attribute index is {}, expected a unique value in 0…{}", g.where(), index,
                  names.size() - 1);
    }
    const auto i = static_cast<std::size_t>(index);
    seen[i] = true;
    NodeSet& set = c.mesh.node_sets[i];
    set.name = name;
    c.boundary_conditions[i] = parse_boundary_condition(
        g.read_string_attribute("condition"), fmt::format("{}: attribute condition", g.where()));
    const std::vector<double> normal = g.read_double_array_attribute("normal");
    if (normal.size() != 2 || !std::isfinite(normal[0]) || !std::isfinite(normal[1])) {
      throw Error("{}: attribute normal: expected 2 finite values", g.where());
    }
    set.normal = Vec2(normal[0], normal[1]);
    const std::string path = fmt::format("/boundary/{}/nodes", name);
    const Rows entries = reader.define_rows(path, TypeClass::integer, 0, "entry", "n_set");
    set.nodes = reader.indices(path, 0, entries, below(nodes.count, "n_nodes"));
  }
}

void require_kind(const Reader& reader, CheckpointKind actual,
                  std::initializer_list<CheckpointKind> expected, std::string_view expected_text) {
  for (auto kind : expected) {
    if (kind == actual) return;
  }
  throw Error("{}: is a {} checkpoint, expected kind {}", reader.label(), to_string(actual),
              expected_text);
}

std::optional<CheckpointMotion> read_motion(const Reader& reader) {
  if (!reader.file().contains("motion")) return std::nullopt;
  const hdf5::Group g = reader.file().open_group("motion");
  CheckpointMotion m;
  m.start_time = g.read_double_attribute("start_time");
  m.step = g.read_double_attribute("step");
  m.base = g.read_string_attribute("base");
  m.input = g.read_string_attribute("input");
  m.base_time = g.read_double_attribute("base_time");
  m.base_displacement = Vec2(g.read_double_attribute("base_displacement_x"),
                             g.read_double_attribute("base_displacement_y"));
  if (!m.base_displacement.allFinite() || !std::isfinite(m.base_time)) {
    throw Error("{}: attributes base_time, base_displacement_x, base_displacement_y must be finite",
                g.where());
  }
  if (!std::isfinite(m.start_time) || !(m.step > 0.0) || !std::isfinite(m.step)) {
    throw Error("{}: attributes start_time = {}, step = {} (expected finite, step > 0)", g.where(),
                m.start_time, m.step);
  }
  if (m.base != "rigid" && m.base != "compliant") {
    throw Error("{}: attribute base is \"{}\" (expected \"rigid\" or \"compliant\")", g.where(),
                m.base);
  }
  if (m.input != "incident" && m.input != "outcrop") {
    throw Error("{}: attribute input is \"{}\" (expected \"incident\" or \"outcrop\")", g.where(),
                m.input);
  }
  const Rows samples = reader.define_rows("/motion/acceleration", TypeClass::floating_point, 2,
                                          "sample", "n_samples");
  if (samples.count < 1) throw Error("{}: no samples", g.where());
  m.acceleration = reader.vectors<2>("/motion/acceleration", samples);
  m.velocity = reader.vectors<2>("/motion/velocity", samples);
  m.displacement = reader.vectors<2>("/motion/displacement", samples);
  if (g.has_attribute("record_end_time")) {
    m.record_end_time = g.read_double_attribute("record_end_time");
    const double last = m.start_time + m.step * static_cast<double>(samples.count - 1);
    if (!(m.record_end_time >= last - 0.5 * m.step) || !std::isfinite(m.record_end_time)) {
      throw Error("{}: attribute record_end_time = {} s, before the last sample ({} s)", g.where(),
                  m.record_end_time, last);
    }
  }
  return m;
}

TransferSettings read_transfer(const Reader& reader) {
  const hdf5::Group group = reader.file().open_group("transfer");
  TransferSettings t;
  read_attributes(group, t, transfer_attributes);
  if (!std::isfinite(t.transfer_time) || !std::isfinite(t.rbf_shape)) {
    throw Error("{}: attributes transfer_time and rbf_shape must be finite", group.where());
  }
  return t;
}

}  // namespace

// -----------------------------------------------------------------------------------------
// Public interface

CheckpointMotion checkpoint_motion(const GroundMotion& motion, std::string base,
                                   std::string input) {
  return {.start_time = motion.start_time(),
          .step = motion.step(),
          .acceleration = motion.acceleration_samples(),
          .velocity = motion.velocity_samples(),
          .displacement = motion.displacement_samples(),
          .base = std::move(base),
          .input = std::move(input),
          .record_end_time =
              motion.cut() ? motion.record_end_time() : std::numeric_limits<double>::quiet_NaN()};
}

GroundMotion ground_motion(const CheckpointMotion& motion) {
  return GroundMotion(motion.start_time, motion.step, motion.acceleration, motion.velocity,
                      motion.displacement, motion.record_end_time);
}

GroundMotion grid_motion(const CheckpointMotion& record) {
  if (record.base != "compliant" || record.input != "incident") return ground_motion(record);
  CheckpointMotion m = record;
  for (auto* samples : {&m.acceleration, &m.velocity, &m.displacement}) {
    for (Vec2& x : *samples) x *= 2.0;
  }
  return ground_motion(m);
}

Vec2 base_position(const CheckpointMotion& motion, const GroundMotion& grid, double time) {
  return motion.base_displacement + (grid.displacement(time) - grid.displacement(motion.base_time));
}

double fem_checkpoint_bytes(const FeFields& state, const Mesh& mesh) {
  return static_cast<double>(
      field_data_bytes(fe_fields, state) + 2 * mesh.nodes.size() * sizeof(Vec2) +
      mesh.connectivity.size() * sizeof(Index) + mesh.material_id.size() * sizeof(std::int32_t));
}

void write_checkpoint(const fs::path& path, const FemCheckpoint& checkpoint) {
  const std::string target = path.string();
  if (checkpoint.header.kind != CheckpointKind::fem) {
    throw Error("{}: cannot write: a fem checkpoint with header kind {}", target,
                to_string(checkpoint.header.kind));
  }
  check_header(target, checkpoint.header);
  // Checked against the free space before the file is begun.
  const double bytes = fem_checkpoint_bytes(checkpoint, checkpoint.mesh);
  write_atomically(
      path,
      [&](const fs::path& temporary) {
        hdf5::File file = hdf5::File::create(temporary, target);
        Writer writer(file, target);
        write_fem(writer, checkpoint);
        file.close();
      },
      bytes);
}

/// The header of a particle checkpoint about to be written to `target`.
void check_particle_header(const std::string& target, const CheckpointHeader& header) {
  if (header.kind == CheckpointKind::fem) {
    throw Error("{}: cannot write: a particle checkpoint needs header kind particles or mpm",
                target);
  }
  check_header(target, header);
}

void write_checkpoint(const fs::path& path, const ParticleCheckpoint& checkpoint) {
  const std::string target = path.string();
  check_particle_header(target, checkpoint.header);
  write_atomically(
      path,
      [&](const fs::path& temporary) {
        hdf5::File file = hdf5::File::create(temporary, target);
        Writer writer(file, target);
        write_particles(writer, checkpoint);
        file.close();
      },
      static_cast<double>(field_data_bytes(particle_fields, checkpoint.particles)));
}

void write_checkpoint_on_ranks(const fs::path& path, const ParticleCheckpoint& checkpoint,
                               std::size_t frozen, const Ranks& ranks) {
  if (!ranks.distributed()) return write_checkpoint(path, checkpoint);
  const std::string target = path.string();
  check_particle_header(target, checkpoint.header);
  // Rows: every rank's active particles in rank order, then every rank's frozen ones.
  const auto count = static_cast<std::int64_t>(checkpoint.particles.count());
  const auto own_frozen = static_cast<std::int64_t>(frozen);
  const std::int64_t own_active = count - own_frozen;
  std::array<std::int64_t, 4> totals{own_active, own_frozen,
                                     checkpoint.particles.affine_velocity.empty() ? 0 : 1,
                                     checkpoint.particles.liquefied.empty() ? 0 : 1};
  ranks.sum(totals);
  const std::int64_t active_before = ranks.exclusive_prefix_sum(own_active);
  const std::int64_t frozen_before = ranks.exclusive_prefix_sum(own_frozen);
  hdf5::RowShare share;
  share.total = static_cast<std::uint64_t>(totals[0] + totals[1]);
  share.ranges = {
      {static_cast<std::uint64_t>(active_before), static_cast<std::uint64_t>(own_active)},
      {static_cast<std::uint64_t>(totals[0] + frozen_before),
       static_cast<std::uint64_t>(own_frozen)}};
  // About the file's size: the particle arrays (the datasets hold them), checked against
  // the free space before the shared write begins.
  const double bytes =
      ranks.sum(static_cast<double>(field_data_bytes(particle_fields, checkpoint.particles)));
  write_atomically_on_ranks(
      path, ranks,
      [&](const fs::path& temporary) {
        hdf5::File file = hdf5::File::create_collective(temporary, target, ranks);
        Writer writer(file, target);
        write_particles(writer, checkpoint, &share, UsedFields{totals[2] > 0, totals[3] > 0});
        file.close();
      },
      bytes);
}

CheckpointHeader read_checkpoint_header(const fs::path& path) {
  const Reader reader(path);
  return read_header(reader.file());
}

namespace {

/// /elements of a fem checkpoint: the element type (`integration` names the rule, `type`
/// the shape it must agree with), connectivity, materials, quality and volumes, and the
/// element fields of the state. Returns the element rows.
Rows read_fem_elements(const Reader& reader, FemCheckpoint& c, const Rows& nodes) {
  const hdf5::Dataset connectivity = reader.file().open_dataset("elements/connectivity");
  c.mesh.element_type =
      parse_element_type(connectivity.read_string_attribute("integration"),
                         fmt::format("{}: attribute integration", connectivity.where()));
  const std::string shape = connectivity.read_string_attribute("type");
  if (parse_element_shape(shape, fmt::format("{}: attribute type", connectivity.where())) !=
      c.mesh.shape()) {
    throw Error("{}: attribute type is \"{}\", but integration \"{}\" is a {} rule",
                connectivity.where(), shape, to_string(c.mesh.element_type),
                to_string(c.mesh.shape()));
  }
  const auto nodes_per_element = static_cast<std::size_t>(c.mesh.nodes_per_element());
  const Rows elements = reader.define_rows("/elements/connectivity", TypeClass::integer,
                                           nodes_per_element, "element", "n_elements");
  c.mesh.connectivity = reader.indices("/elements/connectivity", nodes_per_element, elements,
                                       below(nodes.count, "n_nodes"));
  c.mesh.material_id = reader.material_ids("/elements/material_id", elements, c.materials.size());
  c.jacobian_ratio = reader.doubles("/elements/jacobian_ratio", 0, elements);
  if (reader.file().contains("elements/scaled_jacobian")) {
    c.scaled_jacobian = reader.doubles("/elements/scaled_jacobian", 0, elements);
  }
  c.volume_reference = reader.doubles("/elements/volume_reference", 0, elements);
  require_positive(reader.where("/elements/volume_reference"), c.volume_reference, elements,
                   "reference volume");
  c.volume = reader.doubles("/elements/volume", 0, elements);
  reader.fields(fe_fields, c, RowKind::element, "/elements", elements, c.materials.size());
  return elements;
}

/// /gauss_points of a fem checkpoint: where they are, their weights, εq and the Gauss-point
/// fields of the state.
void read_fem_gauss_points(const Reader& reader, FemCheckpoint& c, const Rows& elements) {
  const Rows gauss =
      reader.define_rows("/gauss_points/element", TypeClass::integer, 0, "Gauss point", "n_gp");
  c.gauss_element =
      reader.indices("/gauss_points/element", 0, gauss, below(elements.count, "n_elements"));
  c.gauss_local_coordinates = reader.vectors<2>("/gauss_points/local_coordinates", gauss);
  c.gauss_coordinates = reader.vectors<2>("/gauss_points/coordinates", gauss);
  c.gauss_weight = reader.doubles("/gauss_points/weight", 0, gauss);
  require_positive(reader.where("/gauss_points/weight"), c.gauss_weight, gauss, "weight");
  c.eps_q = reader.doubles("/gauss_points/eps_q", 0, gauss);
  reader.fields(fe_fields, c, RowKind::gauss_point, "/gauss_points", gauss, c.materials.size());
}

}  // namespace

FemCheckpoint read_fem_checkpoint(const fs::path& path) {
  const Reader reader(path);
  FemCheckpoint c;
  c.header = read_header(reader.file());
  require_kind(reader, c.header.kind, {CheckpointKind::fem}, "fem");
  c.materials = read_materials(reader);

  // Row counts come from the defining datasets; every other dataset must match them.
  const Rows nodes = reader.define_rows("/nodes/reference_coordinates", TypeClass::floating_point,
                                        2, "node", "n_nodes");
  c.mesh.nodes = reader.vectors<2>("/nodes/reference_coordinates", nodes);
  c.coordinates = reader.vectors<2>("/nodes/coordinates", nodes);
  reader.fields(fe_fields, c, RowKind::node, "/nodes", nodes, c.materials.size());
  const Rows elements = read_fem_elements(reader, c, nodes);
  read_fem_gauss_points(reader, c, elements);

  read_boundary(reader, c, nodes);
  c.solver = read_solver(reader);
  c.motion = read_motion(reader);
  return c;
}

namespace {

/// A particle checkpoint's attributes, materials, transfer, settings and motion, and the
/// particle rows of `part` when one is given.
ParticleCheckpoint read_particles(const fs::path& path, const std::optional<Part>& part) {
  const Reader reader(path);
  ParticleCheckpoint c;
  c.header = read_header(reader.file());
  require_kind(reader, c.header.kind, {CheckpointKind::particles, CheckpointKind::mpm},
               "particles or mpm");
  c.materials = read_materials(reader);

  Rows particles =
      reader.define_rows("/particles/coordinates", TypeClass::floating_point, 2, "particle", "n_p");
  c.file_rows = particles.count;
  if (part) {
    if (part->parts > 1) {
      const RowSpan rows = part->rows(particles.count);
      particles.held = hdf5::RowRange{rows.first, rows.count()};
      c.first_row = rows.first;
    }
    // The affine velocity C_p is optional: absent (FLIP/PIC runs, fem2mpm) leaves it
    // empty, and an APIC run then starts its particles with C_p = 0. The B_p = C_p D_p
    // that the first APIC version wrote as /particles/affine_velocity is not read (it
    // needs the grid to convert): such a file restarts as one without affine velocities.
    reader.fields(particle_fields, c.particles, RowKind::particle, "/particles", particles,
                  c.materials.size());
  }

  // A particle file always records its transfer; an mpm checkpoint when it came from one.
  if (c.header.kind == CheckpointKind::particles || reader.file().contains("transfer")) {
    c.transfer = read_transfer(reader);
  }
  c.solver = read_solver(reader);
  c.motion = read_motion(reader);
  return c;
}

}  // namespace

ParticleCheckpoint read_particle_checkpoint(const fs::path& path, const Part& part) {
  return read_particles(path, part);
}

ParticleCheckpoint read_particle_checkpoint_settings(const fs::path& path) {
  return read_particles(path, std::nullopt);
}

}  // namespace slide
